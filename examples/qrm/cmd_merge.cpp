// qrm merge: put the tiles of a render back together. Machines render `--tile i/n` each into
// a directory; copy every part (the .pfm, .csv and manifest files) into one directory and run
//   qrm merge --parts DIR [--out DIR] [--exposure E]
// Every tile 0..n-1 must be there exactly once, made with the same settings; the merged image
// is bit-identical to one rendered in a single run.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "render_job.hpp"

namespace qrm_cli {

namespace {

struct manifest {
  fs::path file;
  std::string kind, settings;
  unsigned tile = 0, tiles = 0;
  std::vector<std::string> images;
  std::string scene;
};

std::string read_text(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  if (!f) throw std::runtime_error(p.string() + ": cannot read");
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// Our own manifests only: {"kind":"...","tile":i,"tiles":n,"settings":{...},"images":["..."]}.
manifest parse_manifest(const fs::path& p) {
  const std::string t = read_text(p);
  manifest m;
  m.file = p;
  auto fail = [&](const std::string& what) { return std::runtime_error(p.string() + ": " + what); };
  std::smatch g;
  if (!std::regex_search(t, g, std::regex("\"kind\":\"([a-z]+)\""))) throw fail("missing \"kind\"");
  m.kind = g[1];
  if (!std::regex_search(t, g, std::regex("\"tile\":([0-9]+),\"tiles\":([0-9]+)"))) throw fail("missing \"tile\"/\"tiles\"");
  m.tile = static_cast<unsigned>(std::stoul(g[1]));
  m.tiles = static_cast<unsigned>(std::stoul(g[2]));
  const auto s0 = t.find("\"settings\":"), s1 = t.find(",\"images\":[");
  if (s0 == std::string::npos || s1 == std::string::npos || s1 < s0) throw fail("missing \"settings\" or \"images\"");
  m.settings = t.substr(s0 + 11, s1 - s0 - 11);
  if (!std::regex_search(m.settings, g, std::regex("^\\{\"scene\":\"([A-Za-z0-9_.-]+)\""))) throw fail("missing the scene's name");
  m.scene = g[1];
  const std::string list = t.substr(s1 + 11);
  const std::regex quoted("\"([A-Za-z0-9_.-]+)\"");
  for (std::sregex_iterator it(list.begin(), list.end(), quoted), end; it != end; ++it)
    m.images.push_back((*it)[1]);
  if (m.images.empty()) throw fail("no images listed");
  return m;
}

}  // namespace

flag_table merge_flags() {
  const char* g = "merge";
  return {
      {"parts", "DIR", "", "the directory the tiles were rendered into (required)", g},
      {"out", "DIR", "the --parts directory", "where the merged images go", g},
      {"exposure", "X", "1", "multiply radiance by X before tone mapping the PNGs", g},
  };
}

int cmd_merge(args& a) {
  a.allow(merge_flags());
  const fs::path parts = a.required("parts");
  if (!fs::is_directory(parts)) throw usage_error("--parts: '" + parts.string() + "' is not a directory");
  render_settings s;
  s.out = a.str("out", parts.string());
  s.exposure = static_cast<float>(a.number("exposure", 1.0));
  if (!(s.exposure > 0)) throw usage_error("--exposure must be positive, got " + a.str("exposure", ""));

  std::vector<manifest> ms;
  for (const auto& e : fs::directory_iterator(parts)) {
    const std::string name = e.path().filename().string();
    if (name.rfind("manifest.part-", 0) == 0 && e.path().extension() == ".json") ms.push_back(parse_manifest(e.path()));
  }
  if (ms.empty()) throw std::runtime_error(parts.string() + ": no manifest.part-*.json (render with --tile i/n first)");
  std::sort(ms.begin(), ms.end(), [](const manifest& x, const manifest& y) { return x.tile < y.tile; });
  const unsigned n = ms[0].tiles;
  for (const manifest& m : ms) {
    if (m.tiles != n || m.settings != ms[0].settings || m.kind != ms[0].kind || m.images != ms[0].images)
      throw std::runtime_error(m.file.string() + ": made with other settings than " + ms[0].file.string() +
                               " (all tiles must come from the same command)");
  }
  for (unsigned i = 0; i < n; ++i) {
    const auto count = std::count_if(ms.begin(), ms.end(), [&](const manifest& m) { return m.tile == i; });
    if (count != 1)
      throw std::runtime_error(parts.string() + ": tile " + std::to_string(i) + " of " + std::to_string(n) +
                               (count == 0 ? " is missing" : " appears " + std::to_string(count) + " times"));
  }
  qrm::io::ensure_directory(s.out);
  std::vector<std::string> written;
  std::vector<qrm::io::image> merged;
  for (const std::string& base : ms[0].images) {
    std::vector<qrm::io::image> pieces;
    for (unsigned i = 0; i < n; ++i)
      pieces.push_back(qrm::io::read_pfm(parts / (base + ".part-" + std::to_string(i) + "-of-" + std::to_string(n) + ".pfm")));
    merged.push_back(qrm::render::merge_tiles(pieces));
    // As render wrote them: light maps with cells shown as blocks, 3D images pixel for pixel.
    const std::size_t block = ms[0].kind == "lightmap" ? std::max<std::size_t>(1, 256 / merged.back().width()) : 1;
    write_image(s, base, merged.back(), written, block);
  }
  if (ms[0].kind == "lightmap") {
    // The CSV rows of each tile, in tile order (= cell order), under one header.
    const std::string base = ms[0].images[0].substr(0, ms[0].images[0].rfind("_estimated"));
    std::string csv;
    for (unsigned i = 0; i < n; ++i) {
      const std::string part =
          read_text(parts / (base + ".part-" + std::to_string(i) + "-of-" + std::to_string(n) + ".csv"));
      csv += i == 0 ? part : part.substr(part.find('\n') + 1);
    }
    qrm::io::write_file_atomically(fs::path(s.out) / (base + ".csv"), csv);
    written.push_back(base + ".csv");
    write_lightmap_figures(s, base, {merged[0], merged[1], merged[2]}, written);
  }
  // A summary like a whole render's, with what the merged images determine: RMSE against the
  // exact image (equal to the whole render's, since the merged images are identical to it).
  std::string scene_base = ms[0].kind == "lightmap"
                               ? ms[0].images[0].substr(0, ms[0].images[0].rfind("_lightmap"))
                               : std::string();
  json_object rmse;
  if (ms[0].kind == "images") {
    const auto& names = ms[0].images;
    auto exact_at = std::find_if(names.begin(), names.end(), [](const std::string& b) {
      return b.size() > 6 && b.ends_with("_exact") && !b.ends_with("_quantum_exact");
    });
    if (exact_at != names.end()) scene_base = exact_at->substr(0, exact_at->size() - 6);
    for (const char* method : {"emulated", "mc", "quantum"}) {  // the order of the whole render's summary
      const auto at = std::find(names.begin(), names.end(), scene_base + "_" + method);
      if (exact_at == names.end() || at == names.end()) continue;
      rmse.add(method, qrm::io::rmse(merged[static_cast<std::size_t>(at - names.begin())],
                                     merged[static_cast<std::size_t>(exact_at - names.begin())]));
    }
  }
  if (scene_base.empty()) scene_base = "merged";
  json_object summary;
  summary.add("scene", ms[0].scene).add("kind", ms[0].kind).add("tiles", n).add("rmse_vs_exact", rmse);
  summary.add("images", json_array::of(written)).add_verbatim("settings", ms[0].settings);
  qrm::io::write_file_atomically(fs::path(s.out) / (scene_base + "_summary.json"), summary.str() + "\n");
  written.push_back(scene_base + "_summary.json");
  std::printf("merged %u tiles into %s:", n, s.out.c_str());
  for (const auto& w : written) std::printf(" %s", w.c_str());
  std::printf("\n");
  return 0;
}

}  // namespace qrm_cli
