// qrm noise: one light-map cell's walk on a noisy quantum computer. For each noise rate: the
// Grover oscillation P(out reads 1 after Q^k A) for k = 0..K against the ideal one (quantum
// trajectories, qrm/noise), and the amplitude estimators run on that noisy oracle over many seeds
// (bias and RMSE against the ideal amplitude; noise-aware MLAE beside the noise-unaware ones), and
// MLAE's error against its cost at growing m, where noise makes the error stop falling.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <qrm/backends/compact.hpp>
#include <qrm/estimation/estimator.hpp>
#include <qrm/estimation/mlae.hpp>
#include <qrm/estimation/oracle.hpp>
#include <qrm/io/csv.hpp>
#include <qrm/io/progress.hpp>
#include <qrm/io/svg_plot.hpp>
#include <qrm/noise.hpp>
#include <qrm/walk/circuit.hpp>
#include <qrm/walk/lightmap.hpp>

#include "commands.hpp"
#include "json.hpp"
#include "scene_arg.hpp"

namespace qrm_cli {

namespace fs = std::filesystem;

namespace {

std::vector<double> parse_rates(const std::string& text) {
  const auto rates = number_list(text);
  if (!rates) throw usage_error("--rates: '" + text + "' is not a comma-separated list of numbers (give e.g. --rates 1e-5,1e-4)");
  for (double v : *rates)
    if (!(v > 0 && v < 1))
      throw usage_error("--rates: '" + short_number(v) + "' is not an error rate in (0, 1) (give e.g. --rates 1e-5,1e-4)");
  return *rates;
}

// The estimators compared on each noisy oracle (FAE without rescaling: the oracle of a rescaled
// problem would need trajectories of its own).
std::vector<std::pair<std::string, qrm::estimator_settings>> noise_estimators(unsigned mlae_m, std::uint64_t shots) {
  std::vector<std::pair<std::string, qrm::estimator_settings>> out;
  qrm::estimator_settings s;
  s.kind = qrm::estimator_kind::mlae;
  s.mlae.m = mlae_m;
  s.mlae.shots = shots;
  out.push_back({"mlae", s});
  s.mlae.noise_aware = true;
  out.push_back({"mlae_noise_aware", s});
  qrm::estimator_settings i;
  i.kind = qrm::estimator_kind::iqae;
  i.iqae.epsilon = 0.01;
  out.push_back({"iqae", i});
  qrm::estimator_settings c;
  c.kind = qrm::estimator_kind::chebae;
  c.chebae.epsilon = 0.01;
  out.push_back({"chebae", c});
  qrm::estimator_settings f;
  f.kind = qrm::estimator_kind::fae;
  f.fae.rescale = false;
  out.push_back({"fae", f});
  return out;
}

}  // namespace

flag_table noise_flags() {
  const char* c = "cell";
  const char* n = "noise";
  const char* e = "estimators";
  const char* r = "run and output";
  flag_table f{
      {"scene", "NAME|FILE", "paper_4x4", "paper_4x4, paper_8x8 or a 2D scene file", c},
      {"x", "X", "1", "the cell's column", c},
      {"y", "Y", "1", "the cell's row", c},
      {"steps", "S", "3", "walk steps, 1..16", c},
      {"channel", "C", "0", "colour channel 0, 1, 2 (R, G, B)", c},
      {"prune", "none|scene|reachable", "reachable", "pruning of the walk circuit", c},
      {"noise", "depolarizing|superconducting|ion", "depolarizing",
       "the noise model: depolarizing at --rates, or a preset (include/qrm/noise/model.hpp)", n},
      {"rates", "R,R,...", "1e-5,3e-5,1e-4", "depolarizing: two-qubit error rates p2 (p1 = p2 / 10), each in (0, 1)", n},
      {"level", "logical|gates", "logical",
       "noise on the logical circuit (one channel per op, rates from its decomposition) or on the decomposed one "
       "(every gate, with the ancillas; slow above ~14 qubits)", n},
      {"kmax", "K", "16", "Grover powers 0..K in the oscillation (0..1024)", n},
      {"trajectories", "N", "100", "quantum trajectories per noise rate (1..1000000)", n},
      {"fuse", "on|off", "on",
       "run the trajectories on fused gates, the errors that fire folded into their blocks (qrm::fused_noisy_circuit; "
       "the same errors and states to rounding); off: gate by gate", n},
      {"seeds", "N", "50", "seeded runs of each estimator per rate (2..100000)", e},
      {"shots", "N", "100", "MLAE shots per power", e},
      {"mlae-m", "M", "4", "MLAE powers 0, 1, 2, .., 2^(M-1) (1..10)", e},
      {"seed", "S", "1", "random seed (integer >= 0)", r},
      {"threads", "T", "0", "worker threads for the trajectories; 0 = all cores", r},
      {"out", "DIR", "noise", "output directory (created): noise.md, noise_oscillation.csv/.svg, noise_convergence.csv/.svg, noise_estimators.csv", r},
  };
  add_progress_flags(f, r);
  return f;
}

int cmd_noise(args& a) {
  a.allow(noise_flags());
  const std::string scene_arg = a.str("scene", "paper_4x4");
  const qrm::scene sc = scene_from_arg(scene_arg);
  auto [cell, wo] = walk_cell_from_flags(a, sc, 1, 1);
  const std::string kind = a.str("noise", "depolarizing");
  if (kind != "depolarizing" && kind != "superconducting" && kind != "ion")
    throw usage_error("--noise must be depolarizing, superconducting or ion, got '" + kind + "'");
  if (kind != "depolarizing" && a.has("rates"))
    throw usage_error("--rates applies to --noise depolarizing; the preset '" + kind + "' has its own rates");
  const std::vector<double> rates = kind == "depolarizing" ? parse_rates(a.str("rates", "1e-5,3e-5,1e-4")) : std::vector<double>{0};
  const std::string level_name = a.str("level", "logical");
  if (level_name != "logical" && level_name != "gates")
    throw usage_error("--level must be logical or gates, got '" + level_name + "'");
  const auto kmax = static_cast<std::uint64_t>(a.integer("kmax", 16, 0, 1024));
  qrm::noisy_oracle_options no;
  no.level = level_name == "gates" ? qrm::noise_level::gates : qrm::noise_level::logical;
  no.trajectories = static_cast<std::size_t>(a.integer("trajectories", 100, 1, 1000000));
  const std::string fuse_arg = a.str("fuse", "on");
  if (fuse_arg != "on" && fuse_arg != "off") throw usage_error("--fuse must be on or off, got '" + fuse_arg + "'");
  no.fuse = fuse_arg == "on";
  const auto seeds = static_cast<std::size_t>(a.integer("seeds", 50, 2, 100000));
  const auto shots = static_cast<std::uint64_t>(a.integer("shots", 100, 1, 1000000000));
  const auto mlae_m = static_cast<unsigned>(a.integer("mlae-m", 4, 1, 10));
  const auto seed = static_cast<std::uint64_t>(a.integer("seed", 1, 0, std::numeric_limits<std::int64_t>::max()));
  no.seed = seed;
  no.threads = static_cast<unsigned>(a.integer("threads", 0, 0, 1024));
  const fs::path out = a.str("out", "noise");
  const qrm::io::progress_options po = progress_from_flags(a);

  const qrm::walk_model m(sc, qrm::king_2d());
  const qrm::walk_program w = qrm::make_walk_program(m, m.light_map_start(cell), wo);
  const double exact = qrm::walk_probability<qrm::compact_backend>(w);
  const qrm::estimation_problem problem{w.circuit, {qrm::control{w.out, true}}};
  const qrm::analytic_oracle ideal(exact);
  const auto estimators = noise_estimators(mlae_m, shots);
  qrm::io::ensure_directory(out);

  std::vector<qrm::noise_model> models;
  for (double r : rates) models.push_back(kind == "depolarizing" ? qrm::depolarizing_noise(r / 10, r) : qrm::noise_preset(kind));
  qrm::io::progress bar("noise " + sc.name(), models.size() * (1 + estimators.size() * seeds), po);

  qrm::io::table osc({"model", "p1", "p2", "k", "ideal", "noisy", "standard_error"});
  qrm::io::table est({"model", "p1", "p2", "estimator", "mean", "bias", "rmse", "mean_reported_se", "bias_over_se",
                      "mean_damping", "max_power"});
  qrm::io::plot plot;
  plot.title = sc.name() + " cell (" + std::to_string(cell[0]) + ", " + std::to_string(cell[1]) + "), " +
               std::to_string(wo.steps) + " steps: P(out = 1) after Q^k A";
  plot.x_label = "Grover power k";
  plot.y_label = "P(out reads 1)";
  {
    qrm::io::plot_series s{"ideal", {}, {}, "#000000", qrm::io::marker::none, true, false};
    for (std::uint64_t k = 0; k <= kmax; ++k) {
      s.x.push_back(static_cast<double>(k));
      s.y.push_back(ideal.probability(k));
    }
    plot.series.push_back(s);
  }
  std::string json = "{\"scene\":" + json_string(sc.name()) + ",\"x\":" + std::to_string(cell[0]) +
                     ",\"y\":" + std::to_string(cell[1]) + ",\"steps\":" + std::to_string(wo.steps) +
                     ",\"level\":" + json_string(level_name) + ",\"exact\":" + json_number(exact) +
                     ",\"trajectories\":" + std::to_string(no.trajectories) + ",\"fuse\":" + (no.fuse ? "true" : "false") +
                     ",\"models\":[";
  // Convergence: plain MLAE at m = 1, 2, .. (powers up to 2^(m-1) <= kmax), RMSE against the
  // ideal amplitude over the same seeds, ideal oracle and each noisy one.
  std::vector<unsigned> conv_m;
  for (unsigned mm = 1; mm <= 10 && (std::uint64_t{1} << (mm - 1)) <= std::max<std::uint64_t>(kmax, 1); ++mm) conv_m.push_back(mm);
  qrm::io::table conv({"model", "m", "a_calls", "rmse"});
  qrm::io::plot cplot;
  cplot.title = "MLAE on " + sc.name() + " cell (" + std::to_string(cell[0]) + ", " + std::to_string(cell[1]) +
                "): error against A applications, ideal and noisy";
  cplot.x_label = "applications of A per estimate";
  cplot.y_label = "RMS error of a";
  cplot.x_scale = cplot.y_scale = qrm::io::axis_scale::log10;
  auto convergence = [&](auto& oracle, const std::string& label, const std::string& colour) {
    qrm::io::plot_series cs{label, {}, {}, colour, qrm::io::marker::square, true, false};
    for (unsigned mm : conv_m) {
      qrm::estimator_settings st;
      st.kind = qrm::estimator_kind::mlae;
      st.mlae.m = mm;
      st.mlae.shots = shots;
      double sq = 0, calls = 0;
      for (std::size_t j = 0; j < seeds; ++j) {
        qrm::rng g = qrm::rng::stream(seed + 1, j);
        const qrm::estimation_result r = qrm::estimate_amplitude(oracle, st, g);
        sq += (r.estimate - exact) * (r.estimate - exact);
        calls += static_cast<double>(r.a_calls);
      }
      const double rmse = std::max(std::sqrt(sq / static_cast<double>(seeds)), 1e-12);
      conv.add_row({label, static_cast<double>(mm), calls / static_cast<double>(seeds), rmse});
      cs.x.push_back(calls / static_cast<double>(seeds));
      cs.y.push_back(rmse);
    }
    cplot.series.push_back(cs);
  };
  {
    qrm::any_oracle io(qrm::analytic_oracle{exact});  // any_oracle: the estimators compiled once
    convergence(io, "ideal", "#000000");
  }
  std::string md_rows, fits;
  int width = 0;
  for (std::size_t mi = 0; mi < models.size(); ++mi) {
    const qrm::noise_model& nm = models[mi];
    const std::string label = kind == "depolarizing" ? "p2=" + short_number(nm.depolarizing_2q) : kind;
    qrm::noisy_oracle noisy(problem, nm, no);
    width = static_cast<int>(noisy.circuits().width);
    noisy.prepare(kmax);
    bar.advance();
    qrm::io::plot_series s{label + " (" + std::to_string(noisy.trajectories()) + " trajectories)", {}, {}, "",
                           qrm::io::marker::circle, true, false};
    for (std::uint64_t k = 0; k <= kmax; ++k) {
      const qrm::trajectory_mean t = noisy.probability_with_error(k);
      osc.add_row({label, nm.depolarizing_1q, nm.depolarizing_2q, static_cast<double>(k), ideal.probability(k), t.mean,
                   t.standard_error});
      s.x.push_back(static_cast<double>(k));
      s.y.push_back(t.mean);
    }
    plot.series.push_back(s);
    qrm::any_oracle oracle(noisy);  // a copy with the trajectories' curve; one estimator instantiation
    {  // the damped model noise-aware MLAE assumes, fitted to the noisy curve (exact probabilities)
      qrm::mlae_options fo;
      for (std::uint64_t k = 0; k <= kmax; ++k) fo.powers.push_back(k);
      fo.shots = 1000;
      fo.exact_probabilities = fo.noise_aware = true;
      qrm::rng unused(0);
      const qrm::estimation_result fit = qrm::maximum_likelihood_amplitude_estimation(oracle, fo, unused);
      const double theta = std::asin(std::sqrt(fit.estimate)), rate = fit.damping.value_or(0.0);
      qrm::io::plot_series fs{label + " fit: a = " + short_number(fit.estimate) + ", decay " + short_number(rate) +
                                  " per A",
                              {}, {}, "", qrm::io::marker::none, true, false};
      for (std::uint64_t k = 0; k <= kmax; ++k) {
        const double K = 2.0 * static_cast<double>(k) + 1.0;
        fs.x.push_back(static_cast<double>(k));
        fs.y.push_back(0.5 * (1 - std::exp(-rate * K) * std::cos(2 * K * theta)));
      }
      plot.series.push_back(fs);
      fits += "| " + label + " | " + short_number(fit.estimate) + " | " + short_number(rate) + " |\n";
    }
    convergence(oracle, label, "");
    json += std::string(mi ? "," : "") + "{\"model\":" + json_string(label) + ",\"estimators\":{";
    for (std::size_t ei = 0; ei < estimators.size(); ++ei) {
      const auto& [name, settings] = estimators[ei];
      double sum = 0, sq = 0, se = 0, damping = 0;
      std::size_t se_count = 0;
      std::uint64_t max_power = 0;
      std::string cannot;  // why the estimator cannot run on this oracle
      for (std::size_t j = 0; j < seeds && cannot.empty(); ++j) {  // the same seeds for every estimator and rate
        qrm::rng g = qrm::rng::stream(seed, j);
        qrm::estimation_result r;
        try {
          r = qrm::estimate_amplitude(oracle, settings, g);
        } catch (const qrm::fae_above_quarter&) {
          cannot = "the noise puts P(good) above 1/4, and FAE runs here without rescale, which needs at most 1/4";
          for (; j < seeds; ++j) bar.advance();
          break;
        }
        sum += r.estimate;
        sq += (r.estimate - exact) * (r.estimate - exact);
        if (r.standard_error) {
          se += *r.standard_error;
          ++se_count;
        }
        if (r.damping) damping += *r.damping;
        for (const auto& round : r.rounds) max_power = std::max(max_power, round.power);
        bar.advance();
      }
      if (!cannot.empty()) {
        md_rows += "| " + label + " | " + name + " | cannot run: " + cannot + " | | | |\n";
        json += std::string(ei ? "," : "") + json_string(name) + ":{\"cannot_run\":" + json_string(cannot) + "}";
        continue;
      }
      const double n = static_cast<double>(seeds);
      const double mean = sum / n, bias = mean - exact, rmse = std::sqrt(sq / n);
      const double mean_se = se_count ? se / static_cast<double>(se_count) : 0.0;
      const double z = mean_se > 0 ? std::fabs(bias) / mean_se : 0.0;
      est.add_row({label, nm.depolarizing_1q, nm.depolarizing_2q, name, mean, bias, rmse, mean_se, z,
                   name == "mlae_noise_aware" ? damping / n : 0.0, static_cast<double>(max_power)});
      md_rows += "| " + label + " | " + name + " | " + short_number(bias) + " | " + short_number(rmse) + " | " +
                 (mean_se > 0 ? short_number(z) : std::string("-")) + " | " + std::to_string(max_power) + " |\n";
      json += std::string(ei ? "," : "") + json_string(name) + ":{\"bias\":" + json_number(bias) +
              ",\"rmse\":" + json_number(rmse) + "}";
    }
    json += "}}";
  }
  bar.finish();
  json += "],\"width\":" + std::to_string(width) + "}";

  std::string md = "# The walk under noise\n\nMade by `qrm noise --scene " + scene_arg + " --x " + std::to_string(cell[0]) +
                   " --y " + std::to_string(cell[1]) + " --steps " + std::to_string(wo.steps) + " --noise " + kind +
                   (kind == "depolarizing" ? " --rates " + a.str("rates", "1e-5,3e-5,1e-4") : std::string()) +
                   " --level " + level_name + " --kmax " + std::to_string(kmax) + " --trajectories " +
                   std::to_string(no.trajectories) + " --seeds " + std::to_string(seeds) + " --shots " +
                   std::to_string(shots) + " --mlae-m " + std::to_string(mlae_m) + " --seed " + std::to_string(seed) +
                   "`.\n\nIdeal P(out = 1) = " + json_number(exact) + "; " + std::to_string(width) +
                   " simulated qubits. Noise: " +
                   (kind == "depolarizing" ? "depolarizing, p1 = p2 / 10 per single-qubit gate, p2 per CNOT"
                                           : "the '" + kind + "' preset") +
                   (level_name == "logical" ? ", applied per logical op as one Pauli channel on its qubits with the "
                                              "rate its decomposition into single-qubit gates and CNOTs implies"
                                            : ", on the decomposed circuit (every gate, relaxation on its schedule)") +
                   ". Estimators run on the noisy oracle with the same seeds; bias and RMSE are against the ideal "
                   "amplitude; bias/SE is |bias| over the mean standard error the estimator reports (MLAE).\n\n"
                   "| noise | estimator | bias | RMSE | bias/SE | max power |\n|---|---|---|---|---|---|\n" +
                   md_rows +
                   "\nThe damped model p_k = (1 - e^(-r (2k+1)) cos(2 (2k+1) theta)) / 2 fitted to each noisy curve "
                   "(k = 0.." + std::to_string(kmax) + ", exact probabilities):\n\n| noise | fitted a | decay r per A |\n|---|---|---|\n" +
                   fits + "\n![Grover oscillation](noise_oscillation.svg)\n\n![MLAE convergence](noise_convergence.svg)\n";
  qrm::io::write_csv(out / "noise_oscillation.csv", osc);
  qrm::io::write_csv(out / "noise_estimators.csv", est);
  qrm::io::write_svg(out / "noise_oscillation.svg", plot);
  qrm::io::write_csv(out / "noise_convergence.csv", conv);
  qrm::io::write_svg(out / "noise_convergence.svg", cplot);
  qrm::io::write_file_atomically(out / "noise.md", md);
  std::printf("%s\n", json.c_str());
  return 0;
}

}  // namespace qrm_cli
