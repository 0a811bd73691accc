// qrm circuit: the A operator of one start point: its metrics at every pruning level, and an
// OpenQASM 3 export.
#include <cmath>
#include <cstdio>
#include <string>

#include <qrm/decompose.hpp>
#include <qrm/io/atomic_file.hpp>
#include <qrm/metrics.hpp>
#include <qrm/qasm.hpp>
#include <qrm/walk.hpp>

#include "commands.hpp"
#include "scene_arg.hpp"

namespace qrm_cli {

namespace {

struct level_report {
  qrm::circuit_metrics logical;
  qrm::decomposed_counts decomposed;
};

level_report report_for(const qrm::walk_model& m, const qrm::walk_start& start, qrm::walk_options o) {
  const auto w = qrm::make_walk_program(m, start, o);
  return {qrm::measure(w.circuit), qrm::decomposed_metrics(w.circuit)};
}

std::string json_level(const level_report& r) {
  std::string s = "{\"width\":" + std::to_string(r.logical.width) +
                  ",\"logical_depth\":" + std::to_string(r.logical.logical_depth) +
                  ",\"gate_count\":" + std::to_string(r.logical.gate_count) +
                  ",\"decomposed_depth\":" + std::to_string(r.decomposed.depth) +
                  ",\"decomposed_cnot_count\":" + std::to_string(r.decomposed.cnot_count) +
                  ",\"decomposed_single_qubit_count\":" + std::to_string(r.decomposed.single_qubit_count) +
                  ",\"decomposed_ancillas\":" + std::to_string(r.decomposed.ancillas) + ",\"gates_by_kind\":{";
  bool first = true;
  for (const auto& [k, v] : r.logical.by_kind) {
    s += std::string(first ? "" : ",") + "\"" + k + "\":" + std::to_string(v);
    first = false;
  }
  return s + "}}";
}

}  // namespace

int cmd_circuit(args& a) {
  a.allow({"scene", "x", "y", "z", "steps", "variant", "prune", "channel", "format", "qasm", "decomposed"});
  const qrm::scene sc = scene_from_arg(a.required("scene"));
  if (sc.dims() != 2) throw usage_error("--scene must be a 2D scene (3D circuits: qrm render --estimator quantum)");
  const auto n = static_cast<std::int64_t>(sc.size()) - 1;
  const std::array<unsigned, 3> cell{static_cast<unsigned>(a.integer("x", 0, 0, n)),
                                     static_cast<unsigned>(a.integer("y", 0, 0, n)), 0};
  qrm::walk_options o;
  o.steps = static_cast<unsigned>(a.integer("steps", 3, 1, 16));
  o.channel = static_cast<int>(a.integer("channel", 0, 0, 2));
  o.prune = pruning_from_arg(a.str("prune", "reachable"));
  const std::string variant = a.str("variant", "faithful");
  if (variant == "history") o.variant = qrm::walk_variant::history;
  else if (variant != "faithful") throw usage_error("--variant must be faithful or history, got '" + variant + "'");
  const std::string format = a.str("format", "json");
  if (format != "json") throw usage_error("--format must be json, got '" + format + "'");
  const bool decomposed_qasm = a.flag("decomposed");
  if (decomposed_qasm && !a.has("qasm")) throw usage_error("--decomposed applies to --qasm FILE; give --qasm");

  const qrm::walk_model m(sc, qrm::king_2d());
  const qrm::walk_start start = m.light_map_start(cell);
  const auto w = qrm::make_walk_program(m, start, o);
  const level_report chosen{qrm::measure(w.circuit), qrm::decomposed_metrics(w.circuit)};

  // The paper's width formula (Section 6): 2 log2 p (position) + log2 d (direction) + s (Le)
  // + (s - 1) (rho) + ceil(log2 s) (steps) + 1 (out) [+ (s - 1) log2 d history qubits].
  const unsigned s = o.steps, p_bits = sc.position_bits(), d_bits = 3;
  const std::size_t formula_width = 2 * p_bits + d_bits + s + (s - 1) + qrm::steps_register_bits(s) + 1 +
                                    (o.variant == qrm::walk_variant::history ? (s - 1) * d_bits : 0);

  std::string json = "{\"scene\":\"" + sc.name() + "\",\"x\":" + std::to_string(cell[0]) + ",\"y\":" +
                     std::to_string(cell[1]) + ",\"steps\":" + std::to_string(s) + ",\"variant\":\"" + variant +
                     "\",\"channel\":" + std::to_string(o.channel) + ",\"prune\":\"" + qrm::pruning_name(o.prune) + "\",";
  const std::string chosen_json = json_level(chosen);
  json += chosen_json.substr(1, chosen_json.size() - 2);  // this level's keys at the top level
  json += ",\"formula_width\":" + std::to_string(formula_width) + ",\"full_width\":" + std::to_string(w.full_width);
  json += ",\"terms_kept\":[";
  for (unsigned i = 0; i < s; ++i) json += std::string(i ? "," : "") + (w.tables.term_kept[i] ? "true" : "false");
  json += "],\"pruning\":{";
  bool first = true;
  for (qrm::pruning p : {qrm::pruning::none, qrm::pruning::scene, qrm::pruning::reachable}) {
    qrm::walk_options q = o;
    q.prune = p;
    json += std::string(first ? "" : ",") + "\"" + qrm::pruning_name(p) + "\":" + json_level(report_for(m, start, q));
    first = false;
  }
  json += "}}";
  std::printf("%s\n", json.c_str());

  if (a.has("qasm")) {
    qrm::qasm_options qo;
    qo.decomposed = decomposed_qasm;
    qrm::io::write_file_atomically(a.str("qasm", ""), qrm::to_qasm(w.circuit, qo));
  }
  return 0;
}

}  // namespace qrm_cli
