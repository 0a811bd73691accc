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
#include "json.hpp"
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

void add_level(json_object& j, const level_report& r) {
  j.add("width", r.logical.width).add("logical_depth", r.logical.logical_depth).add("gate_count", r.logical.gate_count);
  j.add("decomposed_depth", r.decomposed.depth).add("decomposed_cnot_count", r.decomposed.cnot_count);
  j.add("decomposed_single_qubit_count", r.decomposed.single_qubit_count).add("decomposed_ancillas", r.decomposed.ancillas);
  json_object kinds;
  for (const auto& [k, v] : r.logical.by_kind) kinds.add(k, v);
  j.add("gates_by_kind", kinds);
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
      march_flag_row(g),
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
  auto [cell, o] = walk_cell_from_flags(a, sc, 0, 0);
  const std::string variant = a.str("variant", "faithful");
  if (variant == "history") o.variant = qrm::walk_variant::history;
  else if (variant != "faithful") throw usage_error("--variant must be faithful or history, got '" + variant + "'");
  const std::string format = a.str("format", "json");
  if (format != "json") throw usage_error("--format must be json, got '" + format + "'");
  const bool decomposed_qasm = a.flag("decomposed");
  if (decomposed_qasm && !a.has("qasm")) throw usage_error("--decomposed applies to --qasm FILE; give --qasm");

  const qrm::walk_model m(sc, qrm::king_2d(), march_for(march_flag(a), sc));
  const qrm::walk_start start = m.light_map_start(cell);
  const auto w = qrm::make_walk_program(m, start, o);
  const level_report chosen{qrm::circuit_metrics_of(w.circuit), qrm::decomposed_metrics(w.circuit)};

  // The paper's width formula (Section 6): 2 log2 p (position) + log2 d (direction) + s (Le)
  // + (s - 1) (rho) + ceil(log2 s) (steps) + 1 (out) [+ (s - 1) log2 d history qubits]; the
  // surface march adds a distance register per step.
  const unsigned s = o.steps, p_bits = sc.position_bits(), d_bits = 3;
  const std::size_t formula_width = 2 * p_bits + d_bits + s + (s - 1) + qrm::steps_register_bits(s) + 1 +
                                    (o.variant == qrm::walk_variant::history ? (s - 1) * d_bits : 0) +
                                    std::size_t{s} * m.distance_bits();

  json_object j;
  j.add("scene", sc.name()).add("x", cell[0]).add("y", cell[1]).add("steps", s).add("variant", variant);
  j.add("channel", o.channel).add("prune", qrm::pruning_name(o.prune)).add("march", qrm::march_name(m.march()));
  add_level(j, chosen);
  j.add("formula_width", formula_width).add("full_width", w.full_width);
  json_array kept;
  for (unsigned i = 0; i < s; ++i) kept.push(static_cast<bool>(w.tables.term_kept[i]));
  j.add("terms_kept", kept);
  json_object levels;
  for (qrm::pruning p : {qrm::pruning::none, qrm::pruning::scene, qrm::pruning::reachable}) {
    qrm::walk_options q = o;
    q.prune = p;
    json_object l;
    add_level(l, report_for(m, start, q));
    levels.add(qrm::pruning_name(p), l);
  }
  j.add("pruning", levels);
  const std::string json = j.str();
  std::printf("%s\n", json.c_str());

  if (a.has("qasm")) {
    qrm::qasm_options qo;
    qo.decomposed = decomposed_qasm;
    qrm::io::write_file_atomically(a.str("qasm", ""), qrm::to_qasm(w.circuit, qo));
  }
  return 0;
}

}  // namespace qrm_cli
