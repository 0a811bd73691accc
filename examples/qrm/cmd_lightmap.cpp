// qrm lightmap: exact light maps of a 2D scene (faithful and history circuits, classical sum).
#include <cstdio>
#include <string>

#include <qrm/io/csv.hpp>
#include <qrm/walk/lightmap.hpp>

#include "commands.hpp"
#include "json.hpp"
#include "scene_arg.hpp"

namespace qrm_cli {

flag_table lightmap_flags() {
  const char* g = "light map";
  return {
      {"scene", "NAME|FILE", "", "paper_4x4, paper_8x8 or a 2D scene file (required)", g},
      {"exact", "", "", "exact probabilities from the simulated state (required: estimated maps are qrm render's)", g},
      {"steps", "S", "3", "walk steps, 1..12", g},
      march_flag_row(g),
      {"prune", "none|scene|reachable", "reachable", "drop the coin entries and qubits the scene never uses", g},
      {"backend", "dense|compact", "compact", "state vector over all qubits, or only the reachable basis states", g},
      {"format", "csv|json", "csv", "output on stdout", g},
      {"threads", "T", "0", "worker threads; 0 = all cores", g},
  };
}

int cmd_lightmap(args& a) {
  a.allow(lightmap_flags());
  const qrm::scene sc = scene_from_arg(a.required("scene"));
  if (sc.dims() != 2) throw usage_error("--scene must be a 2D scene (3D scenes: qrm render)");
  if (!a.flag("exact"))
    throw usage_error("give --exact (exact probabilities from the simulated state); estimated maps are made by "
                      "`qrm render --scene paper_8x8`");
  qrm::lightmap_options o;
  o.steps = static_cast<unsigned>(a.integer("steps", 3, 1, 12));
  o.prune = pruning_from_arg(a.str("prune", "reachable"));
  o.threads = static_cast<unsigned>(a.integer("threads", 0, 0, 256));
  const std::string backend = a.str("backend", "compact");
  const std::string format = a.str("format", "csv");
  if (format != "csv" && format != "json") throw usage_error("--format must be csv or json, got '" + format + "'");
  if (backend != qrm::dense_backend::name && backend != qrm::compact_backend::name)
    throw usage_error("--backend must be dense or compact, got '" + backend + "'");
  const qrm::walk_model model(sc, qrm::king_2d(), march_for(march_flag(a), sc));
  const auto cells = backend == qrm::dense_backend::name ? qrm::exact_lightmap<qrm::dense_backend>(model, o)
                                                         : qrm::exact_lightmap<qrm::compact_backend>(model, o);
  if (format == "csv") {
    qrm::io::table t({"scene", "x", "y", "channel", "faithful", "history", "classical"});
    for (const auto& c : cells) t.add_row({sc.name(), c.x, c.y, c.channel, c.faithful, c.history, c.classical});
    std::printf("%s", qrm::io::to_csv(t).c_str());
  } else {
    json_array rows;
    for (const auto& c : cells) {
      json_object row;
      row.add("scene", sc.name()).add("x", c.x).add("y", c.y).add("channel", c.channel);
      rows.push(row.add("faithful", c.faithful).add("history", c.history).add("classical", c.classical));
    }
    std::printf("%s\n", rows.str().c_str());
  }
  return 0;
}

}  // namespace qrm_cli
