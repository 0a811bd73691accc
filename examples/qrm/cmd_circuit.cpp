// qrm circuit: the A operator of one start point: its metrics at every pruning level, and an
// OpenQASM 3 export.
#include <cmath>
#include <cstdio>
#include <string>

#include <qrm/circuit/decompose.hpp>
#include <qrm/io/atomic_file.hpp>
#include <qrm/circuit/metrics.hpp>
#include <qrm/circuit/qasm.hpp>
#include <qrm/walk/circuit.hpp>

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
  return {qrm::circuit_metrics_of(w.circuit), qrm::decomposed_metrics(w.circuit)};
}

// Appends `"key":value` pieces one by one (g++ 12 at -O3 warns falsely, -Wrestrict, on long
// chains of std::string temporaries).
struct json_object {
  std::string text = "{";
  json_object& raw(const std::string& key, const std::string& value) {
    if (text.size() > 1) text += ',';
    text += '"';
    text += key;
    text += "\":";
    text += value;
    return *this;
  }
  json_object& num(const std::string& key, std::size_t v) { return raw(key, std::to_string(v)); }
  json_object& str(const std::string& key, const std::string& v) { return raw(key, "\"" + v + "\""); }
  std::string done() const { return text + "}"; }
};

void add_level(json_object& j, const level_report& r) {
  j.num("width", r.logical.width).num("logical_depth", r.logical.logical_depth).num("gate_count", r.logical.gate_count);
  j.num("decomposed_depth", r.decomposed.depth).num("decomposed_cnot_count", r.decomposed.cnot_count);
  j.num("decomposed_single_qubit_count", r.decomposed.single_qubit_count).num("decomposed_ancillas", r.decomposed.ancillas);
  json_object kinds;
  for (const auto& [k, v] : r.logical.by_kind) kinds.num(k, v);
  j.raw("gates_by_kind", kinds.done());
}

}  // namespace

flag_table circuit_flags() {
  const char* g = "circuit";
  const char* q = "export";
  return {
      {"scene", "NAME|FILE", "", "paper_4x4, paper_8x8 or a 2D scene file (required)", g},
      {"x", "X", "0", "the start cell's column", g},
      {"y", "Y", "0", "the start cell's row", g},
      {"steps", "S", "3", "walk steps, 1..16", g},
      {"variant", "faithful|history", "faithful", "the paper's circuit, or the one that keeps each step's direction", g},
      {"prune", "none|scene|reachable", "reachable", "the pruning level reported first and written by --qasm (all levels are listed)", g},
      {"channel", "C", "0", "colour channel 0, 1, 2 (R, G, B)", g},
      {"format", "json", "json", "output on stdout", g},
      {"qasm", "FILE", "", "write the A operator as OpenQASM 3", q},
      {"decomposed", "", "", "with --qasm: single-qubit gates and CNOTs only", q},
  };
}

int cmd_circuit(args& a) {
  a.allow(circuit_flags());
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
  const level_report chosen{qrm::circuit_metrics_of(w.circuit), qrm::decomposed_metrics(w.circuit)};

  // The paper's width formula (Section 6): 2 log2 p (position) + log2 d (direction) + s (Le)
  // + (s - 1) (rho) + ceil(log2 s) (steps) + 1 (out) [+ (s - 1) log2 d history qubits].
  const unsigned s = o.steps, p_bits = sc.position_bits(), d_bits = 3;
  const std::size_t formula_width = 2 * p_bits + d_bits + s + (s - 1) + qrm::steps_register_bits(s) + 1 +
                                    (o.variant == qrm::walk_variant::history ? (s - 1) * d_bits : 0);

  json_object j;
  j.str("scene", sc.name()).num("x", cell[0]).num("y", cell[1]).num("steps", s).str("variant", variant);
  j.num("channel", static_cast<std::size_t>(o.channel)).str("prune", qrm::pruning_name(o.prune));
  add_level(j, chosen);
  j.num("formula_width", formula_width).num("full_width", w.full_width);
  std::string kept = "[";
  for (unsigned i = 0; i < s; ++i) kept += std::string(i ? "," : "") + (w.tables.term_kept[i] ? "true" : "false");
  j.raw("terms_kept", kept + "]");
  json_object levels;
  for (qrm::pruning p : {qrm::pruning::none, qrm::pruning::scene, qrm::pruning::reachable}) {
    qrm::walk_options q = o;
    q.prune = p;
    json_object l;
    add_level(l, report_for(m, start, q));
    levels.raw(qrm::pruning_name(p), l.done());
  }
  j.raw("pruning", levels.done());
  const std::string json = j.done();
  std::printf("%s\n", json.c_str());

  if (a.has("qasm")) {
    qrm::qasm_options qo;
    qo.decomposed = decomposed_qasm;
    qrm::io::write_file_atomically(a.str("qasm", ""), qrm::to_qasm(w.circuit, qo));
  }
  return 0;
}

}  // namespace qrm_cli
