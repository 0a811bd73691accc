// qrm resources: what one light-map cell's (2D) or pixel's (3D) amplitude estimate would cost on a
// fault-tolerant quantum computer (qrm/resources.hpp: Clifford+T counts, surface-code distance,
// T factories, physical qubits and time), for the pruned circuit chosen and the unpruned one
// (in 3D only up to 8^3: the unpruned 16^3 walk lowers to Clifford+T in ~1 minute and 10 GB).
#include <array>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <qrm/backends/compact.hpp>
#include <qrm/estimation/estimator.hpp>
#include <qrm/estimation/oracle.hpp>
#include <qrm/resources.hpp>
#include <qrm/walk/circuit.hpp>
#include <qrm/walk/lightmap.hpp>

#include "commands.hpp"
#include "estimator_args.hpp"
#include "json.hpp"
#include "render_job.hpp"
#include "scene_arg.hpp"

namespace qrm_cli {

namespace {

qrm::hardware hardware_from_flags(args& a) {
  const std::string preset = a.str("preset", "superconducting");
  const bool custom = preset == "custom";
  if (!custom && preset != "superconducting" && preset != "ion")
    throw usage_error("--preset must be superconducting, ion or custom, got '" + preset + "'");
  for (const char* f : {"physical-error", "cycle-time"})
    if (a.has(f) != custom)
      throw usage_error(custom ? "--preset custom needs --physical-error and --cycle-time"
                               : std::string("--") + f + " applies to --preset custom; the " + preset +
                                     " preset has its own");
  if (!custom) return qrm::hardware_preset(preset);
  qrm::hardware hw{"custom", a.number("physical-error", 0), a.number("cycle-time", 0)};
  if (!(hw.physical_error > 0 && hw.physical_error < 0.01))
    throw usage_error("--physical-error must be in (0, 0.01), below the surface code's threshold; got " +
                      a.str("physical-error", ""));
  if (!(hw.cycle_seconds > 0))
    throw usage_error("--cycle-time must be a positive number of seconds, got " + a.str("cycle-time", ""));
  return hw;
}

json_object cost_json(const qrm::estimate_cost& e, std::size_t channels) {
  json_object j;
  j.add("logical_qubits", std::max(e.a.counts.logical_qubits, e.q.counts.logical_qubits));
  j.add("cnot_count", e.a.counts.cnot_count).add("cnot_depth", e.a.counts.cnot_depth);
  j.add("toffoli_count", e.a.counts.toffoli_count).add("rotation_count", e.a.counts.rotation_count);
  j.add("t_count", e.a.t.t_count).add("t_depth", e.a.t.t_depth).add("t_per_rotation", e.a.t.t_per_rotation);
  json_object q;
  q.add("cnot_count", e.q.counts.cnot_count).add("toffoli_count", e.q.counts.toffoli_count);
  q.add("rotation_count", e.q.counts.rotation_count).add("t_count", e.q.t.t_count).add("t_depth", e.q.t.t_depth);
  j.add("grover_iterate", q);
  j.add("code_distance", e.plan.code_distance).add("layout_qubits", e.plan.layout_qubits);
  j.add("distillation_levels", e.plan.distillation_levels).add("factory_units", e.plan.factory_units);
  j.add("data_physical_qubits", e.plan.data_physical_qubits).add("factory_physical_qubits", e.plan.factory_physical_qubits);
  j.add("physical_qubits", e.plan.physical_qubits);
  j.add("seconds_per_a", e.a.seconds).add("seconds_per_grover", e.q.seconds);
  j.add("seconds_per_longest_run", e.plan.seconds).add("seconds_per_estimate", e.seconds);
  j.add("seconds_per_cell", e.seconds * static_cast<double>(channels));
  return j;
}

void print_text(const std::string& label, const qrm::estimate_cost& e, std::size_t channels) {
  std::printf("%s\n", label.c_str());
  std::printf("  A: %zu logical qubits, %zu CNOTs, %zu Toffolis, %zu rotations (%" PRIu64 " T each): T-count %" PRIu64
              ", T-depth %" PRIu64 "\n",
              std::max(e.a.counts.logical_qubits, e.q.counts.logical_qubits), e.a.counts.cnot_count,
              e.a.counts.toffoli_count, e.a.counts.rotation_count, e.a.t.t_per_rotation, e.a.t.t_count, e.a.t.t_depth);
  std::printf("  Q: T-count %" PRIu64 ", T-depth %" PRIu64 "\n", e.q.t.t_count, e.q.t.t_depth);
  std::printf("  surface code: distance %u, %" PRIu64 " physical qubits (%" PRIu64 " data, %" PRIu64
              " in %" PRIu64 " 15-to-1 units over %u levels)\n",
              e.plan.code_distance, e.plan.physical_qubits, e.plan.data_physical_qubits, e.plan.factory_physical_qubits,
              e.plan.factory_units, e.plan.distillation_levels);
  std::printf("  time: A %.4g s, Q %.4g s, the estimate %.4g s (%.3g days), the cell (%zu channels) %.4g s\n",
              e.a.seconds, e.q.seconds, e.seconds, e.seconds / 86400, channels, e.seconds * static_cast<double>(channels));
}

}  // namespace

flag_table resources_flags() {
  const char* c = "circuit";
  const char* h = "hardware and costing";
  flag_table f;
  add_walk_target_flags(f, c);
  const flag rest[] = {
      {"steps", "S", "3 in 2D, 6 in 3D", "walk steps (1..16)", c},
      {"channel", "C", "0", "colour channel (0 R, 1 G, 2 B) whose circuit is costed", c},
      {"prune", "none|scene|reachable", "reachable", "the circuit costed (the unpruned one is reported too, in 3D up to 8^3)", c},
      {"preset", "superconducting|ion|custom", "superconducting",
       "superconducting: p = 1e-3, 1 us per syndrome cycle; ion: 1e-4, 100 us; custom: the two flags below", h},
      {"physical-error", "P", "", "--preset custom: physical error rate per operation, in (0, 0.01)", h},
      {"cycle-time", "SECONDS", "", "--preset custom: one syndrome-extraction cycle", h},
      {"error", "E", "0.001", "total error budget of the longest circuit run, in (0, 1)", h},
      {"toffoli", "7t|4t", "7t", "Toffoli as 7 T gates (T-depth 3) or 4 with an ancilla (T-depth 1)", h},
      {"synthesis", "mixed|ross-selinger", "mixed",
       "T gates per rotation: ceil(0.53 log2(1/e) + 5.3) (Kliuchnikov et al. 2022) or ceil(3 log2(1/e)) (Ross-Selinger)", h},
      {"seed", "S", "1", "random seed of the estimate whose shots are costed", h},
      {"format", "json|text", "json", "output format", h},
      {"image", "", "", "also cost every cell (2D) or distinct pixel start (3D) and channel: the whole image", c},
  };
  for (const flag& r : rest) f.push_back(r);
  for (const flag& e : estimator_flag_table("ae-steps")) f.push_back(e);
  return f;
}

int cmd_resources(args& a) {
  a.allow(resources_flags());
  const walk_target target = walk_target_from_flags(a);
  const render_settings& rs = target.view;
  const qrm::scene& sc = target.scene;
  const bool three_d = target.three_d();
  const std::array<unsigned, 3> cell{target.x, target.y, 0};
  qrm::walk_options o;
  o.steps = static_cast<unsigned>(a.integer("steps", three_d ? 6 : 3, 1, 16));
  o.channel = static_cast<int>(a.integer("channel", 0, 0, 2));
  o.prune = pruning_from_arg(a.str("prune", "reachable"));
  // Measured: the 16^3 walk pruned to the scene lowers to 6.9 M Toffolis in 59 s and 10 GB; at 32^3 it runs out of
  // memory. Only the reachable-set pruning stays small beyond the paper's 8^3.
  if (three_d && sc.size() > 8 && o.prune != qrm::pruning::reachable)
    throw usage_error("--prune " + a.str("prune", "") + " is costed in 3D up to 8^3 voxels (at " +
                      std::to_string(sc.size()) + "^3 its Clifford+T lowering needs 10 GB or more); use --prune reachable");
  const qrm::hardware hw = hardware_from_flags(a);
  const double eps = a.number("error", 1e-3);
  if (!(eps > 0 && eps < 1)) throw usage_error("--error must be in (0, 1), got " + a.str("error", ""));
  qrm::clifford_t_rules rules;
  const std::string toffoli = a.str("toffoli", "7t"), synthesis = a.str("synthesis", "mixed");
  if (toffoli != "7t" && toffoli != "4t") throw usage_error("--toffoli must be 7t or 4t, got '" + toffoli + "'");
  if (synthesis != "mixed" && synthesis != "ross-selinger")
    throw usage_error("--synthesis must be mixed or ross-selinger, got '" + synthesis + "'");
  rules.toffoli = toffoli == "7t" ? qrm::toffoli_costing::seven_t : qrm::toffoli_costing::four_t;
  rules.synthesis = synthesis == "mixed" ? qrm::rotation_synthesis::mixed_fallback : qrm::rotation_synthesis::ross_selinger;
  const auto seed = static_cast<std::uint64_t>(a.integer("seed", 1, 0, std::numeric_limits<std::int64_t>::max()));
  const std::string format = a.str("format", "json");
  if (format != "json" && format != "text") throw usage_error("--format must be json or text, got '" + format + "'");
  const parsed_estimator est = parse_estimator_args(a, "", "fae", "ae-steps");

  const studied_walk studied = study_walk(sc, target.march, cell[0], cell[1], rs.width, rs.height);
  const qrm::walk_model& m = studied.model;
  const qrm::walk_start start = studied.start;
  const std::size_t channels = 3;
  // The estimate whose shots are costed: the estimator run on this cell's exact P(out = 1), as
  // qrm render's light map runs it (same shot counts; the analytic oracle draws the same law).
  auto cost_of = [&](const qrm::walk_start& from, int channel, qrm::pruning prune, qrm::rng g) {
    qrm::walk_options wo = o;
    wo.prune = prune;
    wo.channel = channel;
    const auto w = qrm::make_walk_program(m, from, wo);
    const qrm::estimation_problem problem{w.circuit, {qrm::control{w.out, true}}};
    qrm::analytic_oracle oracle(qrm::walk_probability<qrm::compact_backend>(w));
    const qrm::estimation_result r = qrm::estimate_amplitude(oracle, est.settings, g);
    return std::make_pair(r, qrm::cost_of_estimate(qrm::problem_as_run(problem, est.settings), r, rules, hw, eps));
  };
  const auto [result, chosen] = cost_of(start, o.channel, o.prune, qrm::rng(seed));
  const bool with_unpruned = !three_d || sc.size() <= 8;
  std::optional<qrm::estimate_cost> unpruned;
  if (with_unpruned) unpruned = cost_of(start, o.channel, qrm::pruning::none, qrm::rng(seed)).second;

  // --image: every cell (2D) or distinct pixel start (3D: pixels that see the same voxel from the
  // same direction share one estimate, as in qrm render) and distinct channel, one estimate each
  // (random stream (seed, index * 3 + channel)), run one after another on one machine.
  json_object image;
  double image_total = 0;
  if (a.flag("image")) {
    std::vector<qrm::walk_start> starts;
    if (three_d) {
      std::set<std::pair<std::size_t, int>> seen;
      for (const auto& px : qrm::render::pixel_starts(m, scene_camera(rs, sc)))
        if (px.hit && seen.insert({px.voxel, px.start.direction}).second)
          starts.push_back(qrm::detail::render_start_of(sc, {px.voxel, px.start.direction}));
    } else {
      for (std::size_t c = 0; c < sc.voxel_count(); ++c) starts.push_back(m.light_map_start(sc.coords(c)));
    }
    const auto sources = sc.channel_sources();
    double seconds = 0, longest = 0;
    unsigned distance = 0;
    std::uint64_t qubits = 0, estimates = 0;
    for (std::size_t c = 0; c < starts.size(); ++c)
      for (int ch = 0; ch < 3; ++ch) {
        if (sources[static_cast<std::size_t>(ch)] != ch) continue;  // a copy of another channel
        const auto e = cost_of(starts[c], ch, o.prune, qrm::rng::stream(seed, c * 3 + static_cast<std::size_t>(ch))).second;
        seconds += e.seconds;
        longest = std::max(longest, e.seconds);
        distance = std::max(distance, e.plan.code_distance);
        qubits = std::max(qubits, e.plan.physical_qubits);
        ++estimates;
      }
    image_total = seconds;
    image.add(three_d ? "distinct_starts" : "cells", starts.size()).add("estimates", estimates).add("seconds", seconds);
    image.add("seconds_longest_estimate", longest).add("code_distance_max", distance).add("physical_qubits_max", qubits);
  }

  if (format == "text") {
    std::printf("%s %s, %u steps, channel %d; %s (p = %s, %s s per syndrome cycle), error budget %s\n",
                sc.name().c_str(), studied.where.c_str(), o.steps, o.channel, hw.name.c_str(),
                json_number(hw.physical_error).c_str(), json_number(hw.cycle_seconds).c_str(), json_number(eps).c_str());
    std::printf("estimate: %s, %" PRIu64 " shots, %" PRIu64 " Grover calls, largest power %" PRIu64 "\n",
                result.estimator.c_str(), result.shots, result.grover_calls, chosen.max_power);
    print_text(std::string("pruning ") + qrm::pruning_name(o.prune), chosen, channels);
    if (unpruned)
      print_text("unpruned", *unpruned, channels);
    else
      std::printf("unpruned: not costed above 8^3 voxels (its Clifford+T lowering needs ~10 GB at 16^3)\n");
    if (a.flag("image"))
      std::printf("image (--image): every cell and distinct channel, one after another: %.4g s (%.3g days)\n",
                  image_total, image_total / 86400);
    return 0;
  }
  json_object j;
  j.add("scene", sc.name()).add("x", cell[0]).add("y", cell[1]);
  if (three_d) j.add("width", rs.width).add("height", rs.height).add("voxels", sc.size());
  j.add("steps", o.steps).add("channel", o.channel);
  j.add("prune", qrm::pruning_name(o.prune)).add("march", qrm::march_name(m.march())).add_members(cost_json(chosen, channels));
  if (unpruned) j.add("unpruned", cost_json(*unpruned, channels));
  if (a.flag("image")) j.add("image", image);
  json_object estimate = est.json();
  estimate.add("shots", result.shots).add("grover_calls", result.grover_calls).add("max_power", chosen.max_power);
  j.add("estimate", estimate);
  json_object assumptions;
  assumptions.add("preset", hw.name).add("physical_error", hw.physical_error).add("cycle_seconds", hw.cycle_seconds);
  assumptions.add("error_budget", eps).add("error_logical", chosen.plan.eps_logical);
  assumptions.add("error_distillation", chosen.plan.eps_distillation).add("error_synthesis", chosen.plan.eps_synthesis);
  assumptions.add("rotation_error", chosen.rotation_eps).add("toffoli", toffoli).add("synthesis", synthesis);
  assumptions.add("a_costed", qrm::runs_rescaled(est.settings) ? "A with FAE's rescaling ancilla" : "A");
  assumptions.add("model", "include/qrm/resources/surface_code.hpp: one T state per logical cycle, P_L = 0.03 (p/0.01)^((d+1)/2), "
                           "15-to-1 factories of 11 patches; seconds_per_cell = channels x the estimate of channel's circuit");
  j.add("assumptions", assumptions);
  std::printf("%s\n", j.str().c_str());
  return 0;
}

}  // namespace qrm_cli
