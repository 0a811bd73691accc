// qrm/noise/fused_trajectories.hpp: noisy trajectories that run fused gates (circuit/fuse.hpp).
//
// A trajectory of the gate-level model runs every decomposed gate in its own pass over the
// state, thousands per run of Q. Most of its channels fire in no trajectory at a given moment, so
// fused_noisy_circuit fuses the gates once and reuses the fused ops: where an error fires, only
// the block it falls in is multiplied again with the error inside it.
//
//   - Amplitude damping enters the fused circuit as its no-jump operator K0 (a diagonal gate, not
//     unitary; trajectories.hpp defers the normalisation). A jump needs the state at its event,
//     but none is possible when the event's draw is at least gamma. A run in which some damping
//     draws fall below gamma (with the ion preset about one run of Q in 1000 on the paper's walk,
//     with the superconducting one, gamma summing to ~35 over Q, every run) is cut at those
//     events: the gates between two of them, errors included, are fused for that run alone (at
//     the width and scope chosen for the circuit), and each such event decides on the state it
//     sees, as event by event. Nothing moves across a cut, so the decision sees exactly the state
//     the gate-by-gate run would (a K0 of another qubit moved across it would change the odds).
//   - Each Pauli of a fired error (Pauli channels, dephasing) acts on one qubit q and commutes
//     with every gate between the last gate on q before it (its anchor) and the event, so it
//     applies right after the anchor. An anchor written alone gets the Pauli as the next op; an
//     anchor in a fused block gets that block folded again with the Pauli after it; a Pauli with
//     no gate on q before it comes first.
//   - A trajectory draws the same numbers in the same order as apply_noisy(state, noisy_circuit),
//     so it has the same errors and the same state to rounding (tests/test_noise.cpp: 1e-12).
#pragma once

#include <complex>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "../backends/dense.hpp"
#include "../circuit/fuse.hpp"
#include "../support/random.hpp"
#include "channels.hpp"
#include "trajectories.hpp"

namespace qrm {

// fused_noisy_circuit(circuit, width): see the header comment. width 1..6 fuses the circuit to
// that width (fuse_cheaper_scope), 0 at the width fuse_cheapest chooses, for complex<double>
// amplitudes with default dense_options.
template <int = 0>
class basic_fused_noisy_circuit {
 public:
  static constexpr std::size_t at_start = static_cast<std::size_t>(-1);  // an anchor: before every op

  // A channel of the circuit; anchors[j]: for qubits[j], the index in gates() of the last gate on
  // it before the event, or at_start (damping: its K0 gate's index).
  struct channel {
    std::size_t event = 0;  // index into circuit().events
    std::vector<std::size_t> anchors;
  };

  basic_fused_noisy_circuit(noisy_circuit c, unsigned width = 0)
      : c_(std::move(c)), gates_(c_.width()), fused_(c_.width()) {
    if (width > 6)
      throw std::invalid_argument("fused_noisy_circuit: the fusion width must be 0 (chosen) or 1..6, got " +
                                  std::to_string(width));
    const auto& ops = c_.circuit.ops();
    std::size_t next_op = 0;
    std::vector<std::size_t> last_gate(c_.width(), at_start);
    for (std::size_t ei = 0; ei < c_.events.size(); ++ei) {
      const noise_event& e = c_.events[ei];
      if (e.kind == noise_event_kind::gate) {
        if (e.op != next_op)
          throw std::invalid_argument("fused_noisy_circuit: gate event for op " + std::to_string(e.op) + " where op " +
                                      std::to_string(next_op) + " comes next (the events must run the ops in order)");
        ++next_op;
        for (qubit_index q : op_qubits(ops[e.op])) last_gate[q] = gates_.size();
        gates_.push(ops[e.op]);
        continue;
      }
      if (e.kind == noise_event_kind::damping) {
        last_gate[e.qubits[0]] = gates_.size();
        gates_.apply_gate1(detail::damping_no_jump(e.probability), e.qubits[0], {});
        damps_ = true;
      }
      channel ch{ei, {}};
      for (qubit_index q : e.qubits) ch.anchors.push_back(last_gate[q]);
      channels_.push_back(std::move(ch));
    }
    if (next_op != ops.size())
      throw std::invalid_argument("fused_noisy_circuit: the events run " + std::to_string(next_op) + " of the " +
                                  std::to_string(ops.size()) + " ops");
    fusion_options o = dense_fusion_options<std::complex<double>>();
    o.max_qubits = width;
    fusion_report chosen;
    fused_ = width == 0 ? fuse_cheapest(gates_, o, &chosen, true, &trace_)
                        : fuse_cheaper_scope(gates_, o, &chosen, &trace_);
    cut_options_ = o;
    cut_options_.max_qubits = chosen.max_qubits;
    cut_options_.chunk_qubits = chosen.chunk_qubits;
  }

  const noisy_circuit& circuit() const { return c_; }
  std::size_t width() const { return c_.width(); }
  const program& gates() const { return gates_; }  // the circuit's gates and damping's K0, in order
  const program& fused() const { return fused_; }
  std::size_t fused_ops() const { return fused_.size(); }

  // One trajectory on `state` (the same draws as apply_noisy(state, circuit(), g)); false if
  // damping draws below gamma cut it, so it fused its gates afresh between those events.
  bool apply(trajectory_state& s, rng& g) const {
    if (s.num_qubits() < width())
      throw std::invalid_argument("apply_noisy: the circuit needs " + std::to_string(width()) +
                                  " qubits but the state has " + std::to_string(s.num_qubits()));
    std::vector<fired> errors;
    std::vector<cut> cuts;
    for (const channel& ch : channels_) draw(c_.events[ch.event], ch, g, errors, cuts);
    if (!cuts.empty()) {
      apply_cut(s, errors, cuts);
      detail::normalize_state(s);
      return false;
    }
    if (errors.empty()) {
      s.run_ops(fused_.ops());
    } else {
      const std::vector<op::any> ops = with_errors(errors);
      s.run_ops(ops);
    }
    if (damps_) detail::normalize_state(s);
    return true;
  }

 private:
  struct fired {
    std::size_t anchor;
    qubit_index qubit;
    gate1 pauli;
  };
  // A damping event whose draw fell below gamma: the state decides whether it jumps.
  struct cut {
    std::size_t k0;  // its K0 gate's index in gates_
    qubit_index qubit;
    double gamma, draw;
  };

  // The draws of apply_noisy for one channel: the Paulis of a fired error, one per qubit, or a cut.
  static void draw(const noise_event& e, const channel& ch, rng& g, std::vector<fired>& out, std::vector<cut>& cuts) {
    const double u = g.uniform();
    if (!(u < e.probability)) return;
    if (e.kind == noise_event_kind::damping) {
      cuts.push_back({ch.anchors[0], e.qubits[0], e.probability, u});
    } else if (e.kind == noise_event_kind::dephasing) {
      out.push_back({ch.anchors[0], e.qubits[0], gate::z()});
    } else {
      detail::for_each_random_pauli(e.qubits.size(), g, [&](std::size_t i, const gate1& p) {
        out.push_back({ch.anchors[i], e.qubits[i], p});
      });
    }
  }

  // A run with cuts: the gates and the errors after their anchors, fused piece by piece between
  // the cuts (in event order, so in gates_ order), each cut deciding on the state it sees.
  void apply_cut(trajectory_state& s, const std::vector<fired>& errors, const std::vector<cut>& cuts) const {
    const auto& gates = gates_.ops();
    std::vector<std::vector<const fired*>> after(gates.size());
    program piece(width());
    for (const fired& f : errors) {
      if (f.anchor == at_start)
        piece.apply_gate1(f.pauli, f.qubit, {});
      else
        after[f.anchor].push_back(&f);
    }
    std::size_t next = 0;
    for (std::size_t c = 0; c <= cuts.size(); ++c) {
      const std::size_t end = c < cuts.size() ? cuts[c].k0 : gates.size();
      for (; next < end; ++next) {
        piece.push(gates[next]);
        for (const fired* f : after[next]) piece.apply_gate1(f->pauli, f->qubit, {});
      }
      s.run_ops(fuse(piece, cut_options_).ops());
      piece = program(width());
      if (c == cuts.size()) break;
      detail::apply_damping_drawn(s, cuts[c].qubit, cuts[c].gamma, cuts[c].draw);
      for (const fired* f : after[next]) piece.apply_gate1(f->pauli, f->qubit, {});  // after the K0's place
      ++next;
    }
  }

  // The fused ops with the errors in place (see the header comment).
  std::vector<op::any> with_errors(const std::vector<fired>& errors) const {
    const fusion_trace& t = trace_;
    const auto& fused = fused_.ops();
    std::vector<op::any> out;
    out.reserve(fused.size() + errors.size());
    // Errors by where they go: first, after an op written alone, or into a block (in event order).
    std::vector<std::vector<const fired*>> after(fused.size()), into(t.blocks.size());
    for (const fired& f : errors) {
      if (f.anchor == at_start)
        out.emplace_back(op::gate1_op{f.pauli, f.qubit, {}});
      else if (t.block_of[f.anchor] != fusion_trace::none)
        into[t.block_of[f.anchor]].push_back(&f);
      else
        after[t.output_of[f.anchor]].push_back(&f);
    }
    // The blocks folded again, by where they were written (blocks are numbered in that order; an
    // identity block wrote no op and shares its index with the next).
    std::vector<std::size_t> changed;
    std::vector<bool> replaced(fused.size(), false);
    for (std::size_t b = 0; b < t.blocks.size(); ++b) {
      if (into[b].empty()) continue;
      changed.push_back(b);
      for (std::size_t o = t.blocks[b].first_output; o < t.blocks[b].last_output; ++o) replaced[o] = true;
    }
    std::size_t next = 0;
    for (std::size_t o = 0; o <= fused.size(); ++o) {
      for (; next < changed.size() && t.blocks[changed[next]].first_output == o; ++next)
        out.push_back(refold(t.blocks[changed[next]], into[changed[next]]));
      if (o == fused.size()) break;
      if (!replaced[o]) out.push_back(fused[o]);
      for (const fired* f : after[o]) out.emplace_back(op::gate1_op{f->pauli, f->qubit, {}});
    }
    return out;
  }

  // A block multiplied again with its errors after their anchors.
  op::any refold(const fusion_trace::block& blk, const std::vector<const fired*>& errors) const {
    dense_matrix m = dense_matrix::identity(std::size_t{1} << blk.qubits.size());
    std::size_t folded = 0;
    for (std::size_t i : blk.ops) {
      detail::fold_op(m, gates_.ops()[i], blk.qubits);
      ++folded;
      for (const fired* f : errors)
        if (f->anchor == i) {
          detail::fold_gate1(m, op::gate1_op{f->pauli, f->qubit, {}}, blk.qubits);
          ++folded;
        }
    }
    detail::drop_rounding_residue(m, folded);
    if (blk.qubits.size() == 1) return op::gate1_op{gate::u(m(0, 0), m(0, 1), m(1, 0), m(1, 1)), blk.qubits[0], {}};
    return op::unitary_op{std::move(m), blk.qubits, {}};
  }

  noisy_circuit c_;
  program gates_, fused_;
  fusion_trace trace_;
  fusion_options cut_options_;  // the width and scope the circuit was fused at
  std::vector<channel> channels_;
  bool damps_ = false;
};

using fused_noisy_circuit = basic_fused_noisy_circuit<>;

// apply_noisy(state, fused, g): one trajectory of the fused noisy circuit.
template <int = 0>
inline void apply_noisy(trajectory_state& s, const fused_noisy_circuit& c, rng& g) {
  c.apply(s, g);
}

}  // namespace qrm
