// qrm crossover: at what error would amplitude estimation on a fault-tolerant quantum computer
// beat Monte Carlo on this CPU, for one light-map cell?
//
// Quantum: each estimator at a sweep of budgets, `repetitions` seeded runs on the cell's exact
// P(out = 1) (analytic oracle: the same statistics as simulating every Grover iteration, tested
// in test_estimation); the RMS error in radiance units, and the projected hardware time of the
// mean run (qrm/resources: Clifford+T lowering of A and Q, surface-code plan per preset).
// Classical: the random walk with the circuit's transition probabilities (qrm::monte_carlo) at
// 4^2..4^9 paths, its RMS error against the exact path sum, and its median CPU time on one core.
// Crossover: both curves are fitted as power laws T = c eps^b (least squares in log-log); the
// quantum method is cheaper below eps* where the fits meet, if its slope is shallower. eps* is
// flagged when it lies outside the errors actually measured (an extrapolation).
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <time.h>  // clock_gettime, where POSIX has it

#include <qrm/backends/compact.hpp>
#include <qrm/estimation/estimator.hpp>
#include <qrm/estimation/oracle.hpp>
#include <qrm/io/csv.hpp>
#include <qrm/io/progress.hpp>
#include <qrm/io/svg_plot.hpp>
#include <qrm/resources.hpp>
#include <qrm/support/parallel.hpp>
#include <qrm/walk/circuit.hpp>
#include <qrm/walk/classical.hpp>
#include <qrm/walk/lightmap.hpp>

#include "commands.hpp"
#include "render_job.hpp"
#include "json.hpp"
#include "scene_arg.hpp"

namespace qrm_cli {

namespace fs = std::filesystem;

namespace {

// One budget setting of one method, averaged over the repetitions.
struct measured {
  std::string method, setting;
  double rmse = 0;          // radiance units
  double shots = 0, grover_calls = 0;  // quantum: means per estimate
  std::uint64_t max_power = 0;         // quantum: largest over the repetitions
  bool rescaled = false;               // quantum: runs A with FAE's rescaling ancilla
  double paths = 0;                    // classical
  double cpu_seconds = 0;              // classical: median CPU time of one estimate (one core)
};

// The calling thread's CPU time in seconds, where the platform has a thread clock (else wall
// time). An estimate of a few paths takes microseconds, and wall time also counts whatever
// preempts the thread meanwhile: under load that bent the fitted slope to -1.69, where -2 is the law.
double thread_seconds() {
#ifdef CLOCK_THREAD_CPUTIME_ID
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
#else
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
#endif
}

struct cell_data {
  qrm::walk_start start;
  qrm::walk_program program;
  double exact = 0, classical_mean = 0, radiance_scale = 1;
};

std::vector<std::pair<std::string, qrm::estimator_settings>> quantum_sweep() {
  std::vector<std::pair<std::string, qrm::estimator_settings>> out;
  for (unsigned l = 1; l <= 9; ++l) {
    qrm::estimator_settings s;
    s.kind = qrm::estimator_kind::fae;
    s.fae.maxiter = l;
    s.fae.delta = 0.05;
    out.push_back({"maxiter=" + std::to_string(l), s});
  }
  for (int i = 0; i < 8; ++i) {
    qrm::estimator_settings s;
    s.kind = qrm::estimator_kind::iqae;
    s.iqae.epsilon = 0.05 * std::pow(0.5, i);
    s.iqae.alpha = 0.01;
    out.push_back({"epsilon=" + json_number(s.iqae.epsilon), s});
  }
  for (unsigned m = 1; m <= 9; ++m) {
    qrm::estimator_settings s;
    s.kind = qrm::estimator_kind::mlae;
    s.mlae.m = m;
    out.push_back({"m=" + std::to_string(m), s});
  }
  return out;
}

}  // namespace

flag_table crossover_flags() {
  const char* c = "cell";
  const char* r = "run and output";
  flag_table f;
  add_walk_target_flags(f, c);
  const flag rest[] = {
      {"steps", "S", "3 in 2D, 6 in 3D", "walk steps (1..8)", c},
      {"error", "E", "0.001", "the fault-tolerant error budget of each circuit run, in (0, 1)", c},
      {"repetitions", "R", "64", "seeded runs per budget setting (2..100000)", r},
      {"seed", "S", "1", "random seed (integer >= 0)", r},
      {"threads", "T", "0", "worker threads; 0 = all cores", r},
      {"out", "DIR", "crossover", "output directory (created): crossover.csv, crossover.md, crossover.svg", r},
  };
  for (const flag& r : rest) f.push_back(r);
  add_progress_flags(f, r);
  return f;
}

crossover_result run_crossover(const crossover_request& req) {
  const qrm::scene& sc = req.scene;
  const std::array<unsigned, 3> xy{req.x, req.y, 0};
  const unsigned steps = req.steps;
  const double eps = req.error_budget;
  const std::size_t reps = req.repetitions;
  const std::uint64_t seed = req.seed;
  const unsigned threads = req.threads;
  const fs::path out = req.out;
  const qrm::io::progress_options po = req.progress;
  const bool three_d = sc.dims() == 3;
  const studied_walk studied = study_walk(sc, req.march, xy[0], xy[1], req.width, req.height);
  const qrm::walk_model& m = studied.model;
  const std::string& where = studied.where;
  cell_data cell;
  cell.start = studied.start;
  qrm::walk_options wo;
  wo.steps = steps;
  cell.program = qrm::make_walk_program(m, cell.start, wo);
  cell.exact = qrm::walk_probability<qrm::compact_backend>(cell.program);
  cell.radiance_scale = static_cast<double>(steps) * cell.program.tables.emission_scale;
  cell.classical_mean = qrm::path_sum(m, cell.start, steps, 0);
  if (!(cell.exact > 0))
    throw usage_error(where + " of " + sc.name() + " receives no light in " + std::to_string(steps) +
                      " steps: nothing to estimate");
  qrm::io::ensure_directory(out);

  const auto sweep = quantum_sweep();
  const std::vector<std::uint64_t> path_counts{16, 64, 256, 1024, 4096, 16384, 65536, 262144};
  qrm::io::progress bar("crossover " + sc.name(), (sweep.size() + path_counts.size()) * reps, po);

  // Quantum: errors and call counts (hardware time is computed per preset below).
  std::vector<measured> quantum;
  for (const auto& [label, s] : sweep) {
    std::vector<double> sq(reps), shots(reps), grover(reps);
    std::vector<std::uint64_t> power(reps);
    qrm::detail::parallel_jobs(reps, threads, [&, &s = s](std::size_t j) {
      qrm::rng g = qrm::rng::stream(seed, j);
      qrm::analytic_oracle oracle(cell.exact);
      const qrm::estimation_result r = qrm::estimate_amplitude(oracle, s, g);
      const double err = (r.estimate - cell.exact) * cell.radiance_scale;
      sq[j] = err * err;
      shots[j] = static_cast<double>(r.shots + r.check_shots);
      grover[j] = static_cast<double>(r.grover_calls);
      for (const auto& round : r.rounds) power[j] = std::max(power[j], round.power);
      bar.advance();
    });
    measured p{std::string(qrm::estimator_name(s.kind)), label};
    p.rescaled = qrm::runs_rescaled(s);
    for (std::size_t j = 0; j < reps; ++j) {  // fixed order: deterministic
      p.rmse += sq[j];
      p.shots += shots[j];
      p.grover_calls += grover[j];
      p.max_power = std::max(p.max_power, power[j]);
    }
    p.rmse = std::sqrt(p.rmse / static_cast<double>(reps));
    p.shots /= static_cast<double>(reps);
    p.grover_calls /= static_cast<double>(reps);
    quantum.push_back(p);
  }

  // Classical Monte Carlo: errors and the CPU time of each estimate on its thread (thread_seconds).
  // Each repetition runs every path count in turn, so a change of load on the machine (another
  // process on the core's SMT sibling, say) falls on all counts alike instead of on the few that
  // happened to run meanwhile (timed one count after another, that bent the fit to -1.62 under a
  // sanitizer); the median over the repetitions drops what spikes remain.
  const std::size_t counts = path_counts.size();
  std::vector<double> sq(counts * reps), secs(counts * reps);
  qrm::detail::parallel_jobs(reps, threads, [&](std::size_t j) {
    for (std::size_t c = 0; c < counts; ++c) {
      qrm::rng g = qrm::rng::stream(seed + 1, j);
      const double t0 = thread_seconds();
      const auto est = qrm::monte_carlo(m, cell.start, steps, 0, path_counts[c], g);
      secs[c * reps + j] = thread_seconds() - t0;
      sq[c * reps + j] = (est.mean - cell.classical_mean) * (est.mean - cell.classical_mean);
      bar.advance();
    }
  });
  std::vector<measured> classical;
  for (std::size_t c = 0; c < counts; ++c) {
    measured p{"mc", "paths=" + std::to_string(path_counts[c])};
    p.paths = static_cast<double>(path_counts[c]);
    for (std::size_t j = 0; j < reps; ++j) p.rmse += sq[c * reps + j];  // fixed order: deterministic
    p.rmse = std::sqrt(p.rmse / static_cast<double>(reps));
    const auto row = secs.begin() + static_cast<std::ptrdiff_t>(c * reps);
    std::sort(row, row + static_cast<std::ptrdiff_t>(reps));
    p.cpu_seconds = reps % 2 ? row[reps / 2] : 0.5 * (row[reps / 2 - 1] + row[reps / 2]);
    classical.push_back(p);
  }
  bar.finish();

  // Hardware time of every quantum point, per preset.
  const qrm::clifford_t_rules rules;
  const qrm::estimation_problem problem{cell.program.circuit, {qrm::control{cell.program.out, true}}};
  // Lowered once each: A as it is, and with FAE's rescaling ancilla (qrm::problem_as_run).
  const qrm::estimate_circuits plain = qrm::lower_estimate_circuits(problem, rules);
  qrm::estimator_settings fae;  // the default: FAE with rescaling
  const qrm::estimate_circuits rescaled = qrm::lower_estimate_circuits(qrm::problem_as_run(problem, fae), rules);
  const std::vector<qrm::hardware> presets{qrm::hardware_preset("superconducting"), qrm::hardware_preset("ion")};

  qrm::io::table csv({"method", "setting", "platform", "rmse", "seconds", "shots", "grover_calls", "max_power", "paths",
                      "code_distance", "physical_qubits"});
  std::vector<double> mc_e, mc_t;
  for (const measured& p : classical) {
    csv.add_row({p.method, p.setting, "cpu_one_core", p.rmse, p.cpu_seconds, 0, 0, 0, p.paths, 0, 0});
    mc_e.push_back(p.rmse);
    mc_t.push_back(p.cpu_seconds);
  }
  const qrm::io::line_fit mc_fit = qrm::io::fit_log_log(mc_e, mc_t);
  const double eps_min_mc = *std::min_element(mc_e.begin(), mc_e.end());

  qrm::io::plot plot;
  plot.title = sc.name() + " " + where + ", " + std::to_string(steps) + " steps: time for an RMS error";
  plot.x_label = "RMS error (radiance)";
  plot.y_label = "seconds per estimate";
  plot.x_scale = plot.y_scale = qrm::io::axis_scale::log10;
  plot.series.push_back({"Monte Carlo, one CPU core (measured)", mc_e, mc_t, "#000000", qrm::io::marker::square, true, true});

  std::string md = "# Crossover: fault-tolerant amplitude estimation against Monte Carlo on a CPU\n\n";
  md += "Made by `qrm crossover --scene " + req.scene_arg + " --x " + std::to_string(xy[0]) + " --y " +
        std::to_string(xy[1]) + (three_d ? " --width " + std::to_string(req.width) + " --height " + std::to_string(req.height) : "") +
        " --march " + qrm::march_name(m.march()) + " --steps " + std::to_string(steps) + " --error " + json_number(eps) +
        " --repetitions " + std::to_string(reps) +
        " --seed " + std::to_string(seed) + "`: " + sc.name() + " " + where + ", channel 0.\n\n";
  md += "Assumptions: Clifford+T with Toffoli = 7 T and rotations ceil(0.53 log2(1/e) + 5.3) T; surface code with "
        "error budget " + json_number(eps) + " per circuit run split in thirds, P_L = 0.03 (p/0.01)^((d+1)/2), one T "
        "state per logical cycle, 15-to-1 factories (include/qrm/resources/surface_code.hpp); shots run one after "
        "another on one machine. Monte Carlo: the classical random walk with the circuit's transition "
        "probabilities on one core of the machine that ran this command (each estimate's CPU time on its thread, median over the repetitions). Errors are RMS over the repetitions, in "
        "radiance units; each curve is fitted as a power law T = c eps^b.\n\n";
  md += "Monte Carlo fit: slope " + short_number(mc_fit.slope) + " (1/eps^2 is -2), r^2 = " +
        short_number(mc_fit.r_squared) + ", measured down to eps = " + short_number(eps_min_mc) + ".\n\n";
  md += "| estimator | platform | fit slope | crossover eps* | quantum time at eps* | measured eps range | verdict |\n";
  md += "|---|---|---|---|---|---|---|\n";

  json_object summary;
  summary.add("scene", sc.name()).add("x", xy[0]).add("y", xy[1]).add("steps", steps).add("error_budget", eps);
  summary.add("march", qrm::march_name(m.march())).add("directions", m.direction_count());
  if (three_d) summary.add("width", req.width).add("height", req.height);
  summary.add("mc_slope", mc_fit.slope);
  json_array crossings;
  struct {
    double eps = 0;
    std::string label;
    qrm::io::line_fit fit;
  } best;
  const char* colours[] = {"#1f4e9c", "#c8412b", "#2a8a3e"};
  const char* ion_colours[] = {"#7ea6e0", "#e89a8c", "#8fcf9c"};
  for (const qrm::hardware& hw : presets) {
    int k = 0;
    for (const char* method : {"fae", "iqae", "mlae"}) {
      std::vector<double> e, t;
      for (const measured& p : quantum) {
        if (p.method != method) continue;
        const auto cost = qrm::cost_of_estimate(p.rescaled ? rescaled : plain, p.shots, p.grover_calls, p.max_power, rules,
                                                hw, eps);
        csv.add_row({p.method, p.setting, hw.name, p.rmse, cost.seconds, p.shots, p.grover_calls, p.max_power, 0,
                     cost.plan.code_distance, cost.plan.physical_qubits});
        if (p.rmse > 0) {
          e.push_back(p.rmse);
          t.push_back(cost.seconds);
        }
      }
      const qrm::io::line_fit q = qrm::io::fit_log_log(e, t);
      const double lo = *std::min_element(e.begin(), e.end()), hi = *std::max_element(e.begin(), e.end());
      std::string verdict, at, time_at;
      json_object c;
      c.add("estimator", method).add("platform", hw.name).add("slope", q.slope);
      if (q.slope > mc_fit.slope) {
        // log10 T: q.intercept + q.slope x = mc.intercept + mc.slope x.
        const double x = (mc_fit.intercept - q.intercept) / (q.slope - mc_fit.slope);
        const double eps_star = std::pow(10.0, x), t_star = std::pow(10.0, q.intercept + q.slope * x);
        const bool measured_range = eps_star >= lo && eps_star <= hi && eps_star >= eps_min_mc;
        at = short_number(eps_star);
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.3g s (%.3g years)", t_star, t_star / (365.25 * 86400));
        time_at = buf;
        verdict = std::string("quantum cheaper below eps*") + (measured_range ? "" : " (extrapolated: outside the measured errors)");
        c.add("crossover_eps", eps_star).add("seconds_at_crossover", t_star).add("extrapolated", !measured_range);
        if (eps_star > best.eps) best = {eps_star, std::string(method) + ", " + hw.name, q};
      } else {
        at = "none";
        time_at = "-";
        verdict = "no crossover: the quantum curve is not shallower";
        c.add("crossover_eps", nullptr);
      }
      crossings.push(c);
      char range[64];
      std::snprintf(range, sizeof range, "%.3g .. %.3g", lo, hi);
      md += "| " + std::string(method) + " | " + hw.name + " | " + short_number(q.slope) + " | " + at + " | " + time_at +
            " | " + range + " | " + verdict + " |\n";
      const bool ion = hw.name == "ion";
      plot.series.push_back({std::string(method) + ", " + hw.name + " (projected)", e, t,
                             ion ? ion_colours[k] : colours[k], ion ? qrm::io::marker::triangle : qrm::io::marker::circle,
                             true, false});
      ++k;
    }
  }
  // The earliest crossing, drawn: both fitted power laws extended down to it.
  if (best.eps > 0) {
    const double lo = std::min(best.eps / 2, eps_min_mc), hi = *std::max_element(mc_e.begin(), mc_e.end());
    auto law = [](const qrm::io::line_fit& f, double e) { return std::pow(10.0, f.intercept + f.slope * std::log10(e)); };
    plot.series.push_back({"Monte Carlo fit, extended", {lo, hi}, {law(mc_fit, lo), law(mc_fit, hi)}, "#888888",
                           qrm::io::marker::none, true, false});
    plot.series.push_back({best.label + " fit, extended", {lo, hi}, {law(best.fit, lo), law(best.fit, hi)}, "#f0a030",
                           qrm::io::marker::none, true, false});
    md += "\nThe earliest crossing: " + best.label + " at eps* = " + short_number(best.eps) + ".\n";
  }
  summary.add("crossovers", crossings);
  crossover_result result;
  result.summary_json = summary.str();
  result.markdown = md;
  md += "\n![time against error](crossover.svg)\n";
  qrm::io::write_csv(out / "crossover.csv", csv);
  qrm::io::write_file_atomically(out / "crossover.md", md);
  qrm::io::write_svg(out / "crossover.svg", plot);
  return result;
}

int cmd_crossover(args& a) {
  a.allow(crossover_flags());
  crossover_request r;
  const walk_target target = walk_target_from_flags(a);
  r.scene = target.scene;
  r.scene_arg = target.view.scene;
  r.width = target.view.width;
  r.height = target.view.height;
  r.x = target.x;
  r.y = target.y;
  r.march = target.march;
  const bool three_d = target.three_d();
  r.steps = static_cast<unsigned>(a.integer("steps", three_d ? 6 : 3, 1, 8));
  r.error_budget = a.number("error", 1e-3);
  if (!(r.error_budget > 0 && r.error_budget < 1)) throw usage_error("--error must be in (0, 1), got " + a.str("error", ""));
  r.repetitions = static_cast<std::size_t>(a.integer("repetitions", 64, 2, 100000));
  r.seed = static_cast<std::uint64_t>(a.integer("seed", 1, 0, std::numeric_limits<std::int64_t>::max()));
  r.threads = static_cast<unsigned>(a.integer("threads", 0, 0, 1024));
  r.out = a.str("out", "crossover");
  r.progress = progress_from_flags(a);
  std::printf("%s\n", run_crossover(r).summary_json.c_str());
  return 0;
}

}  // namespace qrm_cli
