// qrm/circuit/fuse.hpp: gate fusion, a pass over programs that any backend can run.
//
// A circuit of small gates (the decomposed walk hardware would run, an imported QASM file, a
// noisy trajectory) costs a dense simulator one pass over the whole state per gate. fuse(p)
// multiplies runs of gates that together touch at most `max_qubits` qubits into one dense
// unitary op, so the backend makes one pass where it made many; the state is the same up to
// rounding (tests/test_fuse.cpp holds fused to unfused within 1e-12 for complex<double>).
//
// The rule (greedy, in program order): every qubit belongs to at most one open block. An op
// joins the blocks that share a qubit with it, largest first, as long as their union with the
// op has at most `max_qubits` qubits; the touched blocks that do not fit are closed (written to
// the output) first. An op that touches no open block joins the largest open block that has
// room for it (a tensor product: one pass over the state instead of two), else opens its own.
// Open blocks act on disjoint qubits, so they commute with each other and closing one early
// never reorders two ops that share a qubit. Controls count as qubits of the
// block (a CNOT is a 2-qubit block). Ops that cannot join (adds and multiplexed ops, whose
// kernels use their structure, gates wider than `max_qubits`, and gates with two or more
// controls unless one block already holds all their qubits: alone they visit a quarter of the
// state or less) close the blocks they touch and pass through unchanged. A block holding a
// single op is written unchanged (its kernel may be cheaper than a dense matrix's: X is a swap,
// a controlled gate visits only its subspace);
// a block of single-qubit gates on one qubit becomes one gate1; a block that never flips some
// of its qubits may be written as smaller matrices under them as controls (detail::block_ops).
//
// A dense backend with chunks (dense_options::chunk_bytes) applies a program in runs, each one
// trip to memory (detail::group_runs). A block that mixes gates of two runs, or turns a control
// outside its run's qubits into a target, can cost a run more: the random suite fused across
// the program made 11 runs where its gates made 10. With fusion_options::chunk_qubits set
// (dense_fusion_options fills it), fuse() first cuts the program into those runs and fuses
// within each, a block keeping to its run's qubits, so fusing never adds a run (9 there).
//
// Which width pays depends on the circuit: a fused block of 6 qubits whose rows hold two
// non-zeros (the decomposed walk: permutations and rotations) costs the dense backend about 2.5
// passes and replaces ~60 gates; a dense one (random rotations) costs ~20. fuse_cheapest(p)
// fuses at every width from 2 to 6 and keeps the program estimated_passes rates cheapest.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "detail/runs.hpp"
#include "ops.hpp"
#include "program.hpp"

namespace qrm {

struct fusion_options {
  unsigned max_qubits = 3;  // widest fused block, 1..6; 3 suits dense circuits (fuse_cheapest chooses by cost)
  bool merge_disjoint = true;  // an op touching no open block joins one with room (tensor product)
  // Fuse within the runs of a dense backend whose chunks hold chunk_qubits qubits, the lowest
  // chunk_low_qubits always among them (see the top of this header); 0: the program in one piece.
  unsigned chunk_qubits = 0;
  unsigned chunk_low_qubits = 0;
};

// What fuse() did.
struct fusion_report {
  unsigned max_qubits = 0;  // the widest block allowed (fuse_cheapest: the width it chose)
  double estimated_passes = 0;  // of the fused program (see estimated_passes)
  std::size_t ops_in = 0, ops_out = 0;
  std::size_t fused_blocks = 0;  // products of two or more ops
  std::size_t block_ops = 0;     // ops written for them (more where a block splits by its controls: detail::block_ops)
  std::size_t passed_through = 0;  // ops that could not join a block
  std::vector<std::size_t> blocks_by_width;  // [k]: fused blocks on k qubits
  unsigned chunk_qubits = 0;  // fused within runs over this many qubits (0: across the program)
};

// Where each input op of fuse() went, for a caller that changes a few blocks afterwards (noise
// trajectories insert the Pauli errors that fire into the blocks they fall in and reuse the rest:
// noise/fused_trajectories.hpp).
struct fusion_trace {
  static constexpr std::size_t none = static_cast<std::size_t>(-1);
  struct block {
    std::vector<std::size_t> ops;  // input ops, in an order that applies them correctly
    std::vector<qubit_index> qubits;  // sorted
    std::size_t first_output = 0, last_output = 0;  // the output ops written for it (maybe none: an identity)
  };
  std::vector<std::size_t> output_of;  // per input op written alone: its output index; none if in a block
  std::vector<std::size_t> block_of;   // per input op in a fused block: its index in blocks; none if alone
  std::vector<block> blocks;
};

// The helpers below are templates only so that they are compiled where fuse() is used, not in
// every unit that includes the umbrella header (see program.hpp).
namespace detail {

// The ops of one open block and the qubits they touch.
struct fusion_block {
  std::vector<std::size_t> ops;  // indices into the input program, in program order
  std::vector<qubit_index> qubits;
};

// Local index of each block qubit: bit j of a matrix index is qubits[j] (sorted ascending).
template <int = 0>
inline unsigned local_bit(const std::vector<qubit_index>& qubits, qubit_index q) {
  return static_cast<unsigned>(std::lower_bound(qubits.begin(), qubits.end(), q) - qubits.begin());
}

// Applies a gate1 op (with its controls) to every column of m, in the block's local bits.
template <int = 0>
inline void fold_gate1(dense_matrix& m, const op::gate1_op& o, const std::vector<qubit_index>& qubits) {
  const std::size_t dim = m.dim;
  const std::size_t t = std::size_t{1} << local_bit(qubits, o.target);
  std::size_t cmask = 0, cvalue = 0;
  for (const control& c : o.controls) {
    const std::size_t b = std::size_t{1} << local_bit(qubits, c.qubit);
    cmask |= b;
    if (c.value) cvalue |= b;
  }
  const gate1& g = o.gate;
  // Most gates of a decomposed circuit are CNOTs and phases (the 8x8 walk: 7955 and 7593 of
  // 18,470): an X swaps two rows and a diagonal gate scales them, the same numbers the general
  // update below gives (its other terms are exact zeros) at a fraction of the work.
  const bool flip = g.m[0][0] == complex{} && g.m[1][1] == complex{} && g.m[0][1] == complex(1) && g.m[1][0] == complex(1);
  const bool diagonal = g.m[0][1] == complex{} && g.m[1][0] == complex{};
  for (std::size_t i = 0; i < dim; ++i) {
    if ((i & t) || (i & cmask) != cvalue) continue;
    complex* const x_row = &m(i, 0);
    complex* const y_row = &m(i | t, 0);
    if (flip) {
      std::swap_ranges(x_row, x_row + dim, y_row);
      continue;
    }
    if (diagonal) {
      if (g.m[0][0] != complex(1))
        for (std::size_t col = 0; col < dim; ++col) x_row[col] *= g.m[0][0];
      if (g.m[1][1] != complex(1))
        for (std::size_t col = 0; col < dim; ++col) y_row[col] *= g.m[1][1];
      continue;
    }
    for (std::size_t col = 0; col < dim; ++col) {
      const complex x = x_row[col], y = y_row[col];
      if (x == complex{} && y == complex{}) continue;  // blocks stay sparse: most columns are zero here
      x_row[col] = g.m[0][0] * x + g.m[0][1] * y;
      y_row[col] = g.m[1][0] * x + g.m[1][1] * y;
    }
  }
}

// Applies a unitary op (with its controls) to every column of m, in the block's local bits.
template <int = 0>
inline void fold_unitary(dense_matrix& m, const op::unitary_op& o, const std::vector<qubit_index>& qubits) {
  const std::size_t dim = m.dim, sub = o.matrix.dim;
  std::vector<std::size_t> offset(sub, 0);
  std::size_t tmask = 0, cmask = 0, cvalue = 0;
  for (std::size_t j = 0; j < o.targets.size(); ++j) {
    const std::size_t b = std::size_t{1} << local_bit(qubits, o.targets[j]);
    tmask |= b;
    for (std::size_t r = 0; r < sub; ++r)
      if ((r >> j) & 1u) offset[r] |= b;
  }
  for (const control& c : o.controls) {
    const std::size_t b = std::size_t{1} << local_bit(qubits, c.qubit);
    cmask |= b;
    if (c.value) cvalue |= b;
  }
  std::vector<complex> in(sub);
  for (std::size_t base = 0; base < dim; ++base) {
    if ((base & tmask) || (base & cmask) != cvalue) continue;
    for (std::size_t col = 0; col < dim; ++col) {
      for (std::size_t r = 0; r < sub; ++r) in[r] = m(base | offset[r], col);
      for (std::size_t r = 0; r < sub; ++r) {
        complex acc{};
        for (std::size_t c = 0; c < sub; ++c) acc += o.matrix(r, c) * in[c];
        m(base | offset[r], col) = acc;
      }
    }
  }
}

// Applies a fusable op (gate1 or unitary) to every column of m, in the block's local bits.
template <int = 0>
inline void fold_op(dense_matrix& m, const op::any& o, const std::vector<qubit_index>& qubits) {
  if (const auto* g = std::get_if<op::gate1_op>(&o))
    fold_gate1(m, *g, qubits);
  else
    fold_unitary(m, *std::get_if<op::unitary_op>(&o), qubits);
}

// Zeroes the real and imaginary parts of a fused block that are no larger than the rounding
// error of its own product (`folded` products, each adding a few units in the last place to an
// entry of at most 1): what should be exact zeros (cos(pi/2), phases that cancel) comes out
// near 1e-17, and would make a block look dense and complex to the kernels (the decomposed walk
// fused at 5 qubits: 18,200 entries of magnitude 1e-65 to 1e-16, beside 15,300 of 1e-2 or more).
template <int = 0>
inline void drop_rounding_residue(dense_matrix& m, std::size_t folded) {
  const double tolerance = 8 * std::numeric_limits<double>::epsilon() * static_cast<double>(folded);
  for (complex& z : m.data)
    z = complex(std::abs(z.real()) <= tolerance ? 0.0 : z.real(), std::abs(z.imag()) <= tolerance ? 0.0 : z.imag());
}

// Qubits of a fusable op (gate1 or unitary, controls included), or empty when it cannot join.
template <int = 0>
inline std::vector<qubit_index> fusable_qubits(const op::any& o) {
  if (o.index() != 0 && o.index() != 1) return {};
  std::vector<qubit_index> q = op_qubits(o);
  std::sort(q.begin(), q.end());
  return q;
}

template <int = 0>
inline std::size_t control_count(const op::any& o) {
  return visit_op(o, [](const auto& x) { return x.controls.size(); });
}

}  // namespace detail

// What the dense backend is expected to spend on a program, in passes over the state (one pass:
// a 1-qubit gate). A gate under c controls visits 2^-c of the state (at least 1/8: below that
// its runs are too short to save whole cache lines). A k-qubit matrix op costs by its rows'
// widest count of non-zeros w (the fixed-width forms) and its dimension d = 2^k (the columns
// each base loads): max(1, 0.4 + 0.03 d + 0.28 w), or 0.3 d - 0.1 when it is dense and 4 < d <= 16
// (the unrolled dense form), twice that with a target on qubits 0-2 (bases gathered instead of
// neighbours). Other ops: one pass. Fitted to ops timed one by one (complex<float>, float
// arithmetic, one thread, AMD EPYC VM, 2026-12-05): the fused decomposed walk (21 qubits, in
// the last-level cache) and the random suite (24 qubits, from memory) at widths 2 to 6; the dense
// form to the same matrices in a cache-sized state, where the dense backend's chunked runs apply
// them (an 8- and 16-row real dense block took 1.9-3.2 and 4.7-6.8 times a 1-qubit gate's time;
// from memory 1.6 and 3.7-4.1; AVX2 AMD EPYC VM, 2026-12-06). Rough (single ops off by up to
// 2x), but it picks the fastest width of both (bench/RESULTS.md).
template <int = 0>
double estimated_passes(const op::any& o) {
  const auto under_controls = [](std::size_t controls) {
    return std::max(std::ldexp(1.0, -static_cast<int>(std::min<std::size_t>(controls, 3))), 0.125);
  };
  if (const auto* g = std::get_if<op::gate1_op>(&o)) return under_controls(g->controls.size());
  if (const auto* u = std::get_if<op::unitary_op>(&o)) {
    const std::size_t d = u->matrix.dim;
    std::size_t w = 0;
    for (std::size_t r = 0; r < d; ++r) {
      std::size_t row = 0;
      for (std::size_t c = 0; c < d; ++c) row += u->matrix(r, c) != complex{};
      w = std::max(w, row);
    }
    const auto dd = static_cast<double>(d), dw = static_cast<double>(w);
    double cost = d <= 4 ? 1.0 : d <= 16 && 2 * w > d ? 0.3 * dd - 0.1 : std::max(1.0, 0.4 + 0.03 * dd + 0.28 * dw);
    if (std::any_of(u->targets.begin(), u->targets.end(), [](qubit_index t) { return t < 3; })) cost *= 2;
    return cost * under_controls(u->controls.size());
  }
  return 1;
}
// ... and summed over a program's ops.
template <int = 0>
double estimated_passes(const program& p) {
  double passes = 0;
  for (const op::any& o : p.ops()) passes += estimated_passes(o);
  return passes;
}

namespace detail {
// The ops a fused block m on `qubits` (sorted) is written as. Qubits the product never flips (no
// non-zero between a row and a column that differ there: a CX's control, a qubit that only
// diagonal gates touched) may become controls instead: each of their values gets its own smaller
// matrix on the other qubits, applied under that value (values with equal matrices share one
// piece under fewer controls), identities (to the rounding of the `folded` products, as in
// drop_rounding_residue: H H) dropped. That halves the
// arithmetic per such qubit, and a control need not lie in the dense backend's chunk where a
// target must (backends/detail/dense_blocked.hpp): the random suite fused at width 3 has 42 such
// qubits in its 73 blocks; written whole, its fused program made 15 chunked runs at 17 qubits a
// chunk against the unfused program's 12, split 13, and ran 0.86-0.95x as long (complex<float>,
// 24 qubits, bench/RESULTS.md). Only qubits 3 and above: a control below that splits no cache line,
// so each value's op would cost the memory of a whole pass. Split when estimated_passes rates the
// pieces cheaper than the block and they are no more ops than went into it.
template <int = 0>
inline std::vector<op::any> block_ops(dense_matrix m, const std::vector<qubit_index>& qubits, std::size_t folded) {
  const double tolerance = 8 * std::numeric_limits<double>::epsilon() * static_cast<double>(folded);
  std::vector<std::size_t> moved, fixed;  // local bits
  for (std::size_t j = 0; j < qubits.size(); ++j) {
    const std::size_t bit = std::size_t{1} << j;
    bool flips = false;
    for (std::size_t r = 0; r < m.dim && !flips; ++r)
      for (std::size_t c = 0; c < m.dim && !flips; ++c) flips = ((r ^ c) & bit) != 0 && m(r, c) != complex{};
    (flips || qubits[j] < 3 ? moved : fixed).push_back(j);
  }
  std::vector<op::any> whole;
  whole.emplace_back(op::unitary_op{m, qubits, {}});
  if (fixed.empty() || moved.empty()) return whole;
  std::vector<qubit_index> targets;
  for (std::size_t j : moved) targets.push_back(qubits[j]);
  const std::size_t sub_dim = std::size_t{1} << moved.size();
  // Each value of the fixed qubits gets its matrix. Two values that differ in one fixed qubit
  // and have equal matrices (to the rounding tolerance) merge into one piece that drops that
  // control, bit by bit: a fixed qubit whose gates cancel (S, then S-dagger) no longer doubles
  // the pieces. The decomposed 8x8 walk (22 qubits, 10,725 gates, width 6) fused to 511 ops
  // where one piece per value made 771 (bench/RESULTS.md).
  struct cube {
    std::size_t value, care;  // over the fixed qubits' bits
    dense_matrix sub;
    bool identity;
  };
  const auto same = [&](const dense_matrix& x, const dense_matrix& y) {
    for (std::size_t e = 0; e < x.data.size(); ++e) {
      const complex d = x.data[e] - y.data[e];
      if (std::abs(d.real()) > tolerance || std::abs(d.imag()) > tolerance) return false;
    }
    return true;
  };
  const std::size_t values = std::size_t{1} << fixed.size();
  std::vector<cube> cubes;
  for (std::size_t v = 0; v < values; ++v) {
    std::size_t base = 0;
    for (std::size_t i = 0; i < fixed.size(); ++i)
      if ((v >> i) & 1u) base |= std::size_t{1} << fixed[i];
    const auto index = [&](std::size_t local) {
      std::size_t at = base;
      for (std::size_t i = 0; i < moved.size(); ++i)
        if ((local >> i) & 1u) at |= std::size_t{1} << moved[i];
      return at;
    };
    dense_matrix sub(sub_dim);
    bool identity = true;
    for (std::size_t r = 0; r < sub_dim; ++r)
      for (std::size_t c = 0; c < sub_dim; ++c) {
        sub(r, c) = m(index(r), index(c));
        const complex off = sub(r, c) - complex(r == c ? 1.0 : 0.0);
        identity = identity && std::abs(off.real()) <= tolerance && std::abs(off.imag()) <= tolerance;
      }
    cubes.push_back({v, values - 1, std::move(sub), identity});
  }
  for (std::size_t i = 0; i < fixed.size(); ++i) {
    const std::size_t bit = std::size_t{1} << i;
    std::vector<cube> merged;
    std::vector<bool> taken(cubes.size(), false);
    for (std::size_t x = 0; x < cubes.size(); ++x) {
      if (taken[x]) continue;
      cube& a = cubes[x];
      if ((a.care & bit) && !(a.value & bit))
        for (std::size_t y = x + 1; y < cubes.size(); ++y) {
          const cube& b = cubes[y];
          if (taken[y] || b.care != a.care || b.value != (a.value | bit) || b.identity != a.identity ||
              !(a.identity || same(a.sub, b.sub)))
            continue;
          taken[y] = true;
          a.care &= ~bit;
          break;
        }
      merged.push_back(std::move(a));
    }
    cubes = std::move(merged);
  }
  std::vector<op::any> pieces;
  for (cube& c : cubes) {
    if (c.identity) continue;
    std::vector<control> cs;
    for (std::size_t i = 0; i < fixed.size(); ++i)
      if ((c.care >> i) & 1u) cs.push_back({qubits[fixed[i]], ((c.value >> i) & 1u) != 0});
    if (sub_dim == 2)
      pieces.emplace_back(op::gate1_op{gate::u(c.sub(0, 0), c.sub(0, 1), c.sub(1, 0), c.sub(1, 1)), targets[0], cs});
    else
      pieces.emplace_back(op::unitary_op{std::move(c.sub), targets, cs});
  }
  double split = 0;
  for (const op::any& o : pieces) split += estimated_passes(o);
  return split < estimated_passes(whole[0]) && pieces.size() <= folded ? pieces : whole;
}

}  // namespace detail

// fuse(p, options, report, trace): p with runs of small gates multiplied into dense unitary ops
// on at most options.max_qubits qubits (see the top of this header); `trace` says where each op went.
template <int = 0>
program fuse(const program& p, fusion_options options = {}, fusion_report* report = nullptr,
             fusion_trace* trace = nullptr) {
  if (options.max_qubits < 1 || options.max_qubits > 6)
    throw std::invalid_argument("fuse: max_qubits must be 1..6, got " + std::to_string(options.max_qubits));
  const std::size_t k = options.max_qubits;
  program out(p.width());
  out.set_registers(p.registers());
  fusion_report rep;
  rep.ops_in = p.size();
  rep.blocks_by_width.assign(k + 1, 0);

  std::vector<detail::fusion_block> blocks;     // open and closed; closed ones are cleared
  std::vector<std::size_t> owner(p.width(), 0);  // block index + 1 of each qubit, 0: none

  if (trace) {
    *trace = {};
    trace->output_of.assign(p.size(), fusion_trace::none);
    trace->block_of.assign(p.size(), fusion_trace::none);
  }
  auto write_op = [&](std::size_t i) {
    if (trace) trace->output_of[i] = out.size();
    out.enter_layer(p.layer_of(i));
    out.push(p.ops()[i]);
  };
  auto close = [&](std::size_t b) {
    detail::fusion_block& blk = blocks[b];
    for (qubit_index q : blk.qubits) owner[q] = 0;
    if (blk.ops.size() == 1) {
      write_op(blk.ops[0]);
    } else {
      std::sort(blk.qubits.begin(), blk.qubits.end());
      dense_matrix m = dense_matrix::identity(std::size_t{1} << blk.qubits.size());
      for (std::size_t i : blk.ops) detail::fold_op(m, p.ops()[i], blk.qubits);
      detail::drop_rounding_residue(m, blk.ops.size());
      if (trace) {
        for (std::size_t i : blk.ops) trace->block_of[i] = trace->blocks.size();
        trace->blocks.push_back({blk.ops, blk.qubits, out.size(), 0});
      }
      out.enter_layer(p.layer_of(blk.ops[0]));
      if (blk.qubits.size() == 1) {
        out.push(op::gate1_op{gate::u(m(0, 0), m(0, 1), m(1, 0), m(1, 1)), blk.qubits[0], {}});
        ++rep.block_ops;
      } else {
        for (op::any& o : detail::block_ops(std::move(m), blk.qubits, blk.ops.size())) {
          out.push(std::move(o));
          ++rep.block_ops;
        }
      }
      if (trace) trace->blocks.back().last_output = out.size();
      ++rep.fused_blocks;
      ++rep.blocks_by_width[blk.qubits.size()];
    }
    blk = {};
  };

  // The open block with the most qubits that still has room for `extra` more (blocks.size() if
  // none): an op that shares no qubit with any block rides along with it.
  std::vector<std::size_t> open;  // indices of open blocks, plus closed ones not yet dropped
  auto roomiest_fit = [&](std::size_t extra) {
    std::erase_if(open, [&](std::size_t b) { return blocks[b].ops.empty(); });
    std::size_t best = blocks.size();
    for (std::size_t b : open) {
      const std::size_t w = blocks[b].qubits.size();
      if (w + extra <= k && (best == blocks.size() || w > blocks[best].qubits.size())) best = b;
    }
    return best;
  };

  // Fuses the ops `piece` (indices into p, in the order they apply), whose blocks keep to the
  // qubits of `allowed`: an op reaching outside passes through.
  auto fuse_piece = [&](std::span<const std::size_t> piece, std::uint64_t allowed) {
    for (const std::size_t i : piece) {
      const op::any& o = p.ops()[i];
      const std::vector<qubit_index> q = detail::fusable_qubits(o);
      bool outside = false;
      for (qubit_index x : q) outside |= x >= 64 || ((allowed >> x) & 1u) == 0;
      // Blocks the op touches (each once) and the size of their union with the op.
      std::vector<std::size_t> touched;
      std::size_t width = 0;
      const std::vector<qubit_index> all = q.empty() ? op_qubits(o) : q;
      for (qubit_index x : all) {
        if (owner[x] == 0) {
          ++width;
          continue;
        }
        const std::size_t b = owner[x] - 1;
        if (std::find(touched.begin(), touched.end(), b) == touched.end()) {
          touched.push_back(b);
          width += blocks[b].qubits.size();
        }
      }
      // A gate with two or more controls alone visits a quarter of the state or less; in a block
      // it would cost a whole dense pass. It joins only a block that already holds all its qubits.
      const bool sparse_alone =
          detail::control_count(o) >= 2 && !(touched.size() == 1 && width == blocks[touched[0]].qubits.size());
      // Cannot join: close what it touches, pass it through.
      if (q.empty() || q.size() > k || sparse_alone || outside) {
        for (std::size_t b : touched) close(b);
        write_op(i);
        ++rep.passed_through;
        continue;
      }
      // The op joins every touched block it keeps open: keep the largest ones while the union
      // still fits and close the others (their ops precede this one and act on qubits disjoint
      // from the kept blocks, so writing them first reorders nothing that does not commute).
      std::sort(touched.begin(), touched.end(),
                [&](std::size_t x, std::size_t y) { return blocks[x].qubits.size() > blocks[y].qubits.size(); });
      std::size_t union_width = q.size();
      std::vector<std::size_t> kept;
      for (std::size_t b : touched) {
        std::size_t shared = 0;
        for (qubit_index x : q) shared += owner[x] == b + 1;
        if (union_width + blocks[b].qubits.size() - shared <= k) {
          union_width += blocks[b].qubits.size() - shared;
          kept.push_back(b);
        } else {
          close(b);
        }
      }
      std::size_t into;
      if (!kept.empty()) {  // merge the kept blocks into the first one
        into = kept[0];
        for (std::size_t t = 1; t < kept.size(); ++t) {
          detail::fusion_block& other = blocks[kept[t]];
          for (qubit_index x : other.qubits) owner[x] = into + 1;
          blocks[into].qubits.insert(blocks[into].qubits.end(), other.qubits.begin(), other.qubits.end());
          blocks[into].ops.insert(blocks[into].ops.end(), other.ops.begin(), other.ops.end());
          other = {};
        }
        // Ops of merged blocks act on disjoint qubits, so any interleaving of them is the same
        // product; program order keeps the output readable. The list is sorted but for the ops
        // appended since the last merge: sorting only those and merging keeps this linear (a
        // full sort per op was 18% of fusing the decomposed walk at width 6).
        std::vector<std::size_t>& ops = blocks[into].ops;
        const auto unsorted = std::is_sorted_until(ops.begin(), ops.end());
        std::sort(unsorted, ops.end());
        std::inplace_merge(ops.begin(), unsorted, ops.end());
      } else if (const std::size_t host = options.merge_disjoint ? roomiest_fit(q.size()) : blocks.size();
                 host < blocks.size()) {
        into = host;  // a tensor product: one pass where the op alone would make its own
      } else {
        into = blocks.size();
        blocks.emplace_back();
        open.push_back(into);
      }
      detail::fusion_block& blk = blocks[into];
      blk.ops.push_back(i);
      for (qubit_index x : q)
        if (owner[x] == 0) {
          owner[x] = into + 1;
          blk.qubits.push_back(x);
        }
    }
  };

  // The pieces fused one after the other: the runs of detail::group_runs, each with its qubits
  // (a block reaching outside them would widen the run), or the whole program.
  detail::run_plan pieces;
  const bool within_runs = options.chunk_qubits != 0 && options.chunk_qubits < p.width();
  if (within_runs) {
    pieces = detail::group_runs(p.ops(), options.chunk_qubits,
                                (std::uint64_t{1} << std::min(options.chunk_low_qubits, options.chunk_qubits)) - 1);
  } else {
    pieces.order.resize(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) pieces.order[i] = i;
    pieces.runs.push_back({0, p.size(), ~std::uint64_t{0}});
  }
  for (const detail::op_run& piece : pieces.runs) {
    const std::uint64_t allowed = piece.local ? piece.local : ~std::uint64_t{0};
    fuse_piece(std::span<const std::size_t>(pieces.order).subspan(piece.first, piece.last - piece.first), allowed);
    for (std::size_t b = 0; b < blocks.size(); ++b)  // close what is still open, in the order the blocks were opened
      if (!blocks[b].ops.empty()) close(b);
  }
  rep.ops_out = out.size();
  rep.max_qubits = options.max_qubits;
  rep.chunk_qubits = within_runs ? options.chunk_qubits : 0;
  if (report) {  // the estimate scans every block: only for a caller who asks
    rep.estimated_passes = estimated_passes(out);
    *report = std::move(rep);
  }
  return out;
}

// fuse_cheaper_scope(p, options, report, trace): with options.chunk_qubits set and a width of 2 or 3,
// fuse() both within runs and across the program and keep the one estimated_passes rates cheaper
// (within runs on a tie); at widths 4-6, across only: their 16- to 64-row blocks wait on
// arithmetic in every scalar type (detail::memory_bound_dim), so the backend applies them op by
// op and a run boundary only cuts them. Measured (one thread, AMD EPYC VM, 2026-12-07,
// bench/RESULTS.md): the random suite (24 qubits) fused within runs is rated 120.4 passes against
// 122.9 across and ran 3-9% faster; the decomposed walk (21 qubits, 6-qubit blocks) is rated 205.4
// against 184.9 and ran 11-25% slower within runs.
template <int = 0>
program fuse_cheaper_scope(const program& p, fusion_options options, fusion_report* report = nullptr,
                           fusion_trace* trace = nullptr) {
  if (options.max_qubits > 3) options.chunk_qubits = 0;
  fusion_report rep;
  program best = fuse(p, options, &rep, trace);
  if (options.chunk_qubits != 0) {
    fusion_report across_rep;
    fusion_trace across_trace;
    options.chunk_qubits = 0;
    program across = fuse(p, options, &across_rep, trace ? &across_trace : nullptr);
    if (across_rep.estimated_passes < rep.estimated_passes) {
      best = std::move(across);
      rep = std::move(across_rep);
      if (trace) *trace = std::move(across_trace);
    }
  }
  if (report) *report = std::move(rep);
  return best;
}

// fuse_cheapest(p, options, report, compare_scopes, trace): fuse() at the width from 2 to 6
// (merge_disjoint on, the other options as given) whose program estimated_passes rates cheapest,
// the narrowest on a tie. Width 1 only merges gates on one qubit, which width 2 does too. With
// options.chunk_qubits set, each width is fused as fuse_cheaper_scope chooses, or within runs
// only when compare_scopes is false.
template <int = 0>
program fuse_cheapest(const program& p, fusion_options options, fusion_report* report = nullptr,
                      bool compare_scopes = true, fusion_trace* trace = nullptr) {
  program best;
  fusion_report best_report;
  fusion_trace best_trace, candidate_trace;
  fusion_trace* const candidate = trace ? &candidate_trace : nullptr;
  options.merge_disjoint = true;
  for (unsigned k = 2; k <= 6; ++k) {
    fusion_report rep;
    options.max_qubits = k;
    program f = compare_scopes ? fuse_cheaper_scope(p, options, &rep, candidate) : fuse(p, options, &rep, candidate);
    if (k == 2 || rep.estimated_passes < best_report.estimated_passes) {
      best = std::move(f);
      best_report = std::move(rep);
      if (trace) best_trace = std::move(candidate_trace);
    }
  }
  if (report) *report = std::move(best_report);
  if (trace) *trace = std::move(best_trace);
  return best;
}

// fuse_cheapest(p, report): the same over the whole program (no chunked runs).
template <int = 0>
program fuse_cheapest(const program& p, fusion_report* report = nullptr) {
  return fuse_cheapest(p, fusion_options{}, report);
}

}  // namespace qrm
