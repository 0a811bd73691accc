// qrm/noise/fused_trajectories.hpp: noisy trajectories that run fused gates (circuit/fuse.hpp).
//
// A trajectory of the gate-level model runs every decomposed gate in its own pass over the
// state, thousands per run of Q. Most of its Pauli channels fire in no trajectory at a given
// moment, so fused_noisy_circuit fuses the gates once and reuses the fused ops: where an error
// fires, only the block it falls in is multiplied again with the Pauli inside it.
//
//   - The events are cut into segments at the amplitude-damping events: their jump probability
//     reads the state, so the state must be up to date there. Each segment's gates are fused once
//     (fuse() with a fusion_trace). Pauli channels and dephasing only draw numbers; their errors
//     are Pauli gates.
//   - Each Pauli of a fired error acts on one qubit q and commutes with every gate between the
//     last gate on q before it (its anchor) and the event; so it applies right after the anchor.
//     An anchor written alone gets the Pauli as the next op; an anchor in a fused block gets that
//     block folded again with the Pauli after it (the other blocks are reused unchanged); a Pauli
//     with no gate on q before it in the segment comes first.
//   - A trajectory draws the same numbers in the same order as apply_noisy(state, noisy_circuit),
//     so it has the same errors and the same state to rounding (tests/test_noise.cpp: 1e-12).
// With relaxation (T1) every gate is followed by damping, so segments hold one or two gates and
// nothing fuses; the depolarizing models are where this pays.
#pragma once

#include <algorithm>
#include <complex>
#include <cstddef>
#include <cstdint>
#include <span>
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

// fused_noisy_circuit(circuit, width): see the header comment. width 1..6 fuses every segment
// to that width; 0 lets fuse_cheapest choose per segment (within or across the dense backend's
// chunked runs, as for complex<double> amplitudes with default dense_options).
template <int = 0>
class basic_fused_noisy_circuit {
 public:
  static constexpr std::size_t at_start = static_cast<std::size_t>(-1);  // an anchor: before every op
  static constexpr std::size_t no_damping = static_cast<std::size_t>(-1);

  // A channel (pauli or dephasing) of a segment; anchors[j]: for qubits[j], the index of the last
  // gate on it before the event among the segment's ops, or at_start.
  struct channel {
    std::size_t event = 0;  // index into circuit().events
    std::vector<std::size_t> anchors;
  };
  struct segment {
    program gates;   // the segment's gates, in order
    program fused;   // fuse(gates)
    fusion_trace trace;
    std::vector<channel> channels;
    std::size_t damping = no_damping;  // index of the event that ends the segment, if any
  };

  basic_fused_noisy_circuit(noisy_circuit c, unsigned width = 0) : c_(std::move(c)), width_(width) {
    if (width > 6)
      throw std::invalid_argument("fused_noisy_circuit: the fusion width must be 0 (chosen) or 1..6, got " +
                                  std::to_string(width));
    const auto& ops = c_.circuit.ops();
    std::size_t next_op = 0;
    segment seg{program(c_.width()), {}, {}, {}, no_damping};
    std::vector<std::size_t> last_gate(c_.width(), at_start);
    for (std::size_t ei = 0; ei < c_.events.size(); ++ei) {
      const noise_event& e = c_.events[ei];
      switch (e.kind) {
        case noise_event_kind::gate: {
          if (e.op != next_op)
            throw std::invalid_argument("fused_noisy_circuit: gate event for op " + std::to_string(e.op) + " where op " +
                                        std::to_string(next_op) + " comes next (the events must run the ops in order)");
          ++next_op;
          for (qubit_index q : op_qubits(ops[e.op])) last_gate[q] = seg.gates.size();
          seg.gates.push(ops[e.op]);
          break;
        }
        case noise_event_kind::pauli:
        case noise_event_kind::dephasing: {
          channel ch{ei, {}};
          for (qubit_index q : e.qubits) ch.anchors.push_back(last_gate[q]);
          seg.channels.push_back(std::move(ch));
          break;
        }
        case noise_event_kind::damping:
          seg.damping = ei;
          finish(seg);
          seg = segment{program(c_.width()), {}, {}, {}, no_damping};
          std::fill(last_gate.begin(), last_gate.end(), at_start);
          break;
      }
    }
    if (next_op != ops.size())
      throw std::invalid_argument("fused_noisy_circuit: the events run " + std::to_string(next_op) + " of the " +
                                  std::to_string(ops.size()) + " ops");
    if (seg.gates.size() != 0 || !seg.channels.empty()) finish(seg);
  }

  const noisy_circuit& circuit() const { return c_; }
  std::size_t width() const { return c_.width(); }
  const std::vector<segment>& segments() const { return segments_; }
  // Ops of the fused segments summed (against c_.circuit.size() gates).
  std::size_t fused_ops() const {
    std::size_t n = 0;
    for (const segment& s : segments_) n += s.fused.size();
    return n;
  }

  // One trajectory on `state` (the same draws as apply_noisy(state, circuit(), g)).
  void apply(trajectory_state& s, rng& g) const {
    if (s.num_qubits() < width())
      throw std::invalid_argument("apply_noisy: the circuit needs " + std::to_string(width()) +
                                  " qubits but the state has " + std::to_string(s.num_qubits()));
    std::vector<fired> errors;
    for (const segment& seg : segments_) {
      errors.clear();
      for (const channel& ch : seg.channels) draw(c_.events[ch.event], ch, g, errors);
      if (errors.empty()) {
        s.run_ops(seg.fused.ops());
      } else {
        const std::vector<op::any> ops = with_errors(seg, errors);
        s.run_ops(ops);
      }
      if (seg.damping != no_damping) {
        const noise_event& e = c_.events[seg.damping];
        detail::apply_damping(s, e.qubits[0], e.probability, g);
      }
    }
  }

 private:
  struct fired {
    std::size_t anchor;
    qubit_index qubit;
    gate1 pauli;
  };

  void finish(segment& seg) {
    if (seg.gates.size() > 1) {
      fusion_options o = dense_fusion_options<std::complex<double>>();
      if (width_ == 0) {
        fusion_report chosen;
        (void)fuse_cheapest(seg.gates, o, &chosen);
        o.max_qubits = chosen.max_qubits;
        o.chunk_qubits = chosen.chunk_qubits;
      } else {
        o.max_qubits = width_;
        if (width_ > 3) o.chunk_qubits = 0;
      }
      seg.fused = fuse(seg.gates, o, nullptr, &seg.trace);
    } else {
      seg.fused = seg.gates;
      seg.trace.output_of.assign(seg.gates.size(), 0);
      seg.trace.block_of.assign(seg.gates.size(), fusion_trace::none);
    }
    segments_.push_back(std::move(seg));
  }

  // The draws of apply_noisy for one channel; the Paulis of a fired error, one per qubit.
  static void draw(const noise_event& e, const channel& ch, rng& g, std::vector<fired>& out) {
    if (!(g.uniform() < e.probability)) return;
    if (e.kind == noise_event_kind::dephasing) {
      out.push_back({ch.anchors[0], e.qubits[0], gate::z()});
      return;
    }
    const std::uint64_t strings = (std::uint64_t{1} << (2 * e.qubits.size())) - 1;
    const std::uint64_t r = 1 + g.below(strings);
    for (std::size_t i = 0; i < e.qubits.size(); ++i) switch ((r >> (2 * i)) & 3u) {
        case 1: out.push_back({ch.anchors[i], e.qubits[i], gate::x()}); break;
        case 2: out.push_back({ch.anchors[i], e.qubits[i], gate::y()}); break;
        case 3: out.push_back({ch.anchors[i], e.qubits[i], gate::z()}); break;
        default: break;
      }
  }

  // The segment's fused ops with the errors in place (see the header comment).
  static std::vector<op::any> with_errors(const segment& seg, const std::vector<fired>& errors) {
    const fusion_trace& t = seg.trace;
    const auto& fused = seg.fused.ops();
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
        out.push_back(refold(seg, t.blocks[changed[next]], into[changed[next]]));
      if (o == fused.size()) break;
      if (!replaced[o]) out.push_back(fused[o]);
      for (const fired* f : after[o]) out.emplace_back(op::gate1_op{f->pauli, f->qubit, {}});
    }
    return out;
  }

  // A block multiplied again with its errors after their anchors.
  static op::any refold(const segment& seg, const fusion_trace::block& blk, const std::vector<const fired*>& errors) {
    dense_matrix m = dense_matrix::identity(std::size_t{1} << blk.qubits.size());
    std::size_t folded = 0;
    for (std::size_t i : blk.ops) {
      detail::fold_op(m, seg.gates.ops()[i], blk.qubits);
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
  unsigned width_ = 0;
  std::vector<segment> segments_;
};

using fused_noisy_circuit = basic_fused_noisy_circuit<>;

// apply_noisy(state, fused, g): one trajectory of the fused noisy circuit.
template <int = 0>
inline void apply_noisy(trajectory_state& s, const fused_noisy_circuit& c, rng& g) {
  c.apply(s, g);
}

}  // namespace qrm
