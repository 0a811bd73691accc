// qrm figures: the paper's figures in one run (the README's first command).
//   1. the 8x8 light map of Fig. 4: FAE (maxiter 5, rescaling) on the fully simulated circuit of
//      every cell and channel, next to the exact and classical maps, their difference, and the
//      bilinearly upsampled image;
//   2. the Cornell box (Fig. 1 left) and the two spheres (Fig. 5), 128x128 at the paper's 8^3 voxels
//      and voxel march: the paper's emulator (32 paths per pixel + FAE), the exact path sum, Monte
//      Carlo; fully quantum (every pixel's 3D walk circuit simulated) at 128x128 (the spheres at
//      64x64); then at scale with the surface march: both scenes at 64^3 voxels, 256x256 (exact,
//      Monte Carlo, emulator), and the Cornell box fully quantum at 32^3, 128x128;
//   3. Monte Carlo against the exact image as the path count grows;
//   4. convergence (Fig. 1 centre): error against the number of estimates, with fitted slopes;
//   5. what accuracy costs: error against wall time and against oracle calls, per method.
// Everything lands in --out (default `figures`), with summary.md holding the numbers.
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include <qrm/io/atomic_file.hpp>
#include <qrm/io/pfm.hpp>
#include <qrm/io/svg_plot.hpp>
#include "studies.hpp"

#include "commands.hpp"
#include "render_job.hpp"

namespace qrm_cli {

namespace {

std::string fmt(double v, const char* f = "%.4g") {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

struct figure_log {
  std::string md;
  void line(const std::string& s) { md += s + "\n"; }
};

// Error curves as an SVG (log-log, fitted slopes) and a CSV.
void write_curves(const fs::path& dir, const std::string& base, const std::string& title, const std::string& x_label,
                  const std::vector<std::vector<qrm::render::error_point>>& curves, bool time_axis, figure_log& log) {
  qrm::io::plot p;
  p.title = title;
  p.x_label = x_label;
  p.y_label = "RMS error (radiance)";
  p.x_scale = p.y_scale = qrm::io::axis_scale::log10;
  qrm::io::table t({"method", "setting", "estimates_per_cell", "seconds_per_cell", "rmse"});
  for (const auto& c : curves) {
    qrm::io::plot_series s;
    s.name = c.front().method == "mc" ? "Monte Carlo paths" : c.front().method;
    s.fit = !time_axis;
    for (const auto& pt : c) {
      const double x = time_axis ? pt.seconds : pt.estimates;
      if (x > 0 && pt.rmse > 0) {
        s.x.push_back(x);
        s.y.push_back(pt.rmse);
      }
      t.add_row({pt.method, pt.setting, pt.estimates, pt.seconds, pt.rmse});
    }
    if (s.x.size() >= 2) {
      if (!time_axis) {
        const auto f = qrm::io::fit_log_log(s.x, s.y);
        log.line("| " + s.name + " | " + fmt(f.slope, "%.3f") + " | " + fmt(s.x.front(), "%.3g") + " .. " +
                 fmt(s.x.back(), "%.3g") + " | " + fmt(f.r_squared, "%.3f") + " |");
      }
      p.series.push_back(std::move(s));
    }
  }
  qrm::io::write_svg(dir / (base + ".svg"), p);
  qrm::io::write_csv(dir / (base + ".csv"), t);
}

}  // namespace

flag_table figures_flags() {
  const char* g = "figures";
  flag_table f{
      {"out", "DIR", "figures", "output directory (created)", g},
      {"quick", "", "", "smaller images and sweeps (for tests; minutes become seconds)", g},
      {"seed", "S", "1", "random seed, integer >= 0", g},
      {"threads", "T", "0", "worker threads; 0 = all cores (the result does not depend on it)", g},
  };
  add_progress_flags(f, g);
  return f;
}

int cmd_figures(args& a) {
  a.allow(figures_flags());
  const bool quick = a.flag("quick");
  render_settings s;
  s.out = a.str("out", "figures");
  s.threads = static_cast<unsigned>(a.integer("threads", 0, 0, 1024));
  s.seed = static_cast<std::uint64_t>(a.integer("seed", 1, 0, std::numeric_limits<std::int64_t>::max()));
  s.progress = progress_from_flags(a);
  const qrm::fae_options& fae = s.estimator.fae;  // the paper's: the default settings
  s.estimator_json.add("estimator", "fae").add("delta", fae.delta).add("maxiter", fae.maxiter).add("rescale", fae.rescale);
  const fs::path dir(s.out);
  qrm::io::ensure_directory(dir);
  const auto t_all = std::chrono::steady_clock::now();
  figure_log log;
  log.line("# qrm figures");
  log.line("");
  log.line(std::string("Made by `qrm figures") + (quick ? " --quick" : "") + " --out " + s.out + "` (seed " +
           std::to_string(s.seed) + ").");
  log.line("");

  // 1. The 8x8 light map.
  {
    const qrm::scene sc = qrm::paper_8x8();
    const auto r = render_lightmap(s, sc);
    log.line("## 2D light map (paper_8x8, s = 3, FAE maxiter 5 with rescaling, every Grover iteration simulated)");
    log.line("");
    log.line("| cell-channels | exact value inside the FAE interval | RMSE vs exact | RMSE vs classical | "
             "largest interference | oracle calls | seconds |");
    log.line("|---|---|---|---|---|---|---|");
    log.line("| " + std::to_string(r.cell_channels) + " | " + std::to_string(r.inside_interval) + " (" +
             fmt(100.0 * static_cast<double>(r.inside_interval) / static_cast<double>(r.cell_channels), "%.1f") +
             "%) | " + fmt(r.rmse_vs_exact) + " | " + fmt(r.rmse_vs_classical) + " | " +
             fmt(100 * r.max_interference, "%.1f") + "% | " + fmt(static_cast<double>(r.a_calls), "%.3g") + " | " +
             fmt(r.seconds, "%.2f") + " |");
    log.line("");
  }

  // 2. 3D images: the paper's setting (8^3 voxels, the voxel march, 15 directions), then at
  // scale (the surface march: 64^3 voxels at 256x256; fully quantum at 32^3, 128x128).
  const unsigned size = quick ? 32 : 128;
  auto image_table = [&](const image3d_summary& r) {
    log.line("| method | seconds | RMSE vs exact |");
    log.line("|---|---|---|");
    for (const auto& [m, t] : r.seconds)
      log.line("| " + m + " | " + fmt(t, "%.2f") + " | " +
               (r.rmse_vs_exact.count(m) ? fmt(r.rmse_vs_exact.at(m)) : std::string("(reference)")) + " |");
    log.line("");
  };
  for (const char* name : {"cornell", "spheres"}) {
    render_settings r3 = s;
    r3.scene = name;
    r3.march = qrm::march_mode::voxel;
    r3.width = r3.height = size;
    r3.methods = "exact,mc,emulated";
    const qrm::scene sc = load_render_scene(r3);
    const auto r = render_images_3d(r3, sc);
    log.line(std::string("## ") + sc.name() + ", " + std::to_string(size) + "x" + std::to_string(size) + ", " +
             std::to_string(sc.size()) + "^3 voxels, the paper's voxel march, 15 directions, s = 6 voxel steps, " +
             "32 paths per pixel");
    log.line("");
    image_table(r);
  }
  for (const char* name : {"cornell", "spheres"}) {
    render_settings rq = s;
    rq.scene = name;
    rq.march = qrm::march_mode::voxel;
    rq.width = rq.height = quick ? 16 : (std::string(name) == "cornell" ? 128 : 64);
    rq.methods = "quantum";
    const qrm::scene sc = load_render_scene(rq);
    const auto r = render_images_3d(rq, sc);
    log.line("Fully quantum " + sc.name() + " (" + std::to_string(rq.width) + "x" + std::to_string(rq.height) +
             "): every pixel's 3D walk circuit (32 qubits at s = 6) simulated on the compact backend, " +
             std::to_string(r.distinct_starts) + " distinct walk starts, " + fmt(r.seconds.at("quantum"), "%.1f") +
             " s; FAE statistics from the simulated state's P(out = 1).");
    log.line("");
  }
  const unsigned big = quick ? 16 : 64, big_size = quick ? 32 : 256;
  for (const char* name : {"cornell", "spheres"}) {
    render_settings r3 = s;
    r3.scene = name;
    r3.voxels = big;
    r3.width = r3.height = big_size;
    r3.paths = 64;
    r3.methods = "exact,mc,emulated";
    const qrm::scene sc = load_render_scene(r3);
    const auto r = render_images_3d(r3, sc);
    log.line(std::string("## ") + sc.name() + " at scale, " + std::to_string(big_size) + "x" + std::to_string(big_size) +
             ", " + std::to_string(sc.size()) + "^3 voxels, the surface march (a step is a bounce), " +
             std::to_string(r3.directions_for(sc)) + " directions, s = 6 bounces, 64 paths per pixel");
    log.line("");
    image_table(r);
  }
  {
    render_settings rq = s;
    rq.scene = "cornell";
    rq.voxels = quick ? 16 : 32;
    rq.width = rq.height = quick ? 16 : 128;
    rq.methods = "exact,quantum";
    const qrm::scene sc = load_render_scene(rq);
    const auto r = render_images_3d(rq, sc);
    log.line("## " + sc.name() + " fully quantum at scale, " + std::to_string(rq.width) + "x" + std::to_string(rq.height) +
             ", the surface march, " + std::to_string(rq.directions_for(sc)) + " directions, s = 6 bounces");
    log.line("");
    log.line("Every distinct pixel start's walk circuit simulated on the compact backend (" +
             std::to_string(r.distinct_starts) + " starts), FAE statistics from its P(out = 1): " +
             fmt(r.seconds.at("quantum"), "%.1f") + " s; exact P(out = 1) inside the FAE interval for " +
             std::to_string(r.inside_interval) + " of " + std::to_string(r.start_channels) +
             " start-channels; circuits of " + fmt(r.qubits_mean, "%.1f") + " qubits on average (at most " +
             std::to_string(r.qubits_max) + "), final states of " + fmt(r.nonzeros_mean, "%.3g") +
             " nonzero amplitudes on average (at most " + std::to_string(r.nonzeros_max) + "), " +
             fmt(1e3 * r.seconds_per_start, "%.3g") + " ms per start-channel to build and simulate; RMSE vs the exact image " +
             fmt(r.rmse_vs_exact.at("quantum")) +
             "; largest relative difference between the faithful walk and the classical path sum (interference) " +
             fmt(100 * r.max_interference, "%.2g") + "%.");
    log.line("");
  }

  // 3. Monte Carlo against exact as paths grow (Cornell box).
  {
    const qrm::scene sc = qrm::render::cornell_box(8);
    const qrm::walk_model m(sc, qrm::sphere_directions(15, 3));
    const auto cam = qrm::render::box_scene_camera(8, size, size);
    qrm::render::render_options ro;
    ro.steps = 6;
    ro.threads = s.threads;
    const auto exact = qrm::render::render_exact(m, cam, ro);
    log.line("## Monte Carlo path tracing against the exact image (Cornell box)");
    log.line("");
    log.line("| paths per pixel | RMSE |");
    log.line("|---|---|");
    qrm::io::table t({"paths_per_pixel", "rmse"});
    for (std::uint64_t n : {std::uint64_t{8}, std::uint64_t{32}, std::uint64_t{128}, std::uint64_t{512}}) {
      if (quick && n > 32) break;
      const double e = qrm::io::rmse(qrm::render::render_monte_carlo(m, cam, n, s.seed, ro).mean, exact);
      log.line("| " + std::to_string(n) + " | " + fmt(e) + " |");
      t.add_row({n, e});
    }
    qrm::io::write_csv(dir / "mc_vs_exact.csv", t);
    log.line("");
  }

  // 4-5. Convergence and cost, on the same light-map cells.
  {
    const qrm::walk_model m(qrm::paper_8x8(), qrm::king_2d());
    const auto cells = qrm::render::study_cells(m, 3, quick ? 8 : 24);
    qrm::render::study_options so;
    so.repetitions = quick ? 2 : 8;
    so.seed = s.seed;
    so.threads = s.threads;
    std::vector<std::uint64_t> paths;
    for (int k = 0; k <= (quick ? 10 : 16); k += 2) paths.push_back(std::uint64_t{1} << k);
    std::vector<std::vector<qrm::render::error_point>> curves;
    curves.push_back(qrm::render::monte_carlo_curve(m, cells, 3, paths, so));
    for (qrm::estimator_kind k : qrm::all_estimators) {
      if (k == qrm::estimator_kind::mc) continue;
      const int levels = quick ? 3 : (k == qrm::estimator_kind::canonical ? 6 : 8);
      curves.push_back(qrm::render::estimator_curve(cells, qrm::render::budget_sweep(k, levels), so));
    }
    log.line("## Convergence (" + std::to_string(cells.size()) + " light-map cell-channels, " +
             std::to_string(so.repetitions) + " seeds each)");
    log.line("");
    log.line("Least-squares slope of log(RMS error) against log(estimates): paths for Monte Carlo, applications of "
             "the ray-marching circuit A for the quantum estimators. The paper reports -0.471 (MC) and -1.407 (quantum).");
    log.line("");
    log.line("| method | slope | estimates per cell | r^2 |");
    log.line("|---|---|---|---|");
    write_curves(dir, "convergence", "Error against the number of estimates", "estimates per cell", curves, false, log);
    log.line("");

    // What accuracy costs: every Grover iteration simulated, so seconds are the simulator's.
    qrm::render::study_options st = so;
    st.grover = qrm::render::grover_mode::simulated;
    st.repetitions = quick ? 1 : 3;
    const auto few = std::vector<qrm::render::study_cell>(cells.begin(), cells.begin() + std::min<std::size_t>(cells.size(), 8));
    std::vector<std::vector<qrm::render::error_point>> cost;
    cost.push_back(qrm::render::monte_carlo_curve(m, few, 3, paths, st));
    for (qrm::estimator_kind k : qrm::all_estimators) {
      if (k == qrm::estimator_kind::mc) continue;
      cost.push_back(qrm::render::estimator_curve(few, qrm::render::budget_sweep(k, quick ? 2 : 5), st));
    }
    figure_log ignore;
    write_curves(dir, "accuracy_time", "Error against wall time (simulated circuits)", "seconds per cell", cost, true,
                 ignore);
    write_curves(dir, "accuracy_calls", "Error against oracle calls (simulated circuits)", "estimates per cell", cost,
                 false, ignore);
    log.line("## What accuracy costs (" + std::to_string(few.size()) +
             " cell-channels, every Grover iteration simulated on the compact backend)");
    log.line("");
    log.line("| method | setting | estimates per cell | seconds per cell | RMS error |");
    log.line("|---|---|---|---|---|");
    for (const auto& c : cost)
      for (const auto& pt : c)
        log.line("| " + pt.method + " | " + pt.setting + " | " + fmt(pt.estimates, "%.3g") + " | " +
                 fmt(pt.seconds, "%.3g") + " | " + fmt(pt.rmse, "%.3g") + " |");
    log.line("");
  }
  // What it would cost on a fault-tolerant quantum computer, against Monte Carlo on this CPU.
  {
    crossover_request r;
    r.scene = qrm::paper_8x8();
    r.scene_arg = "paper_8x8";
    r.repetitions = quick ? 8 : 64;
    r.seed = s.seed;
    r.threads = s.threads;
    r.out = s.out;
    r.progress = s.progress;
    const crossover_result x = run_crossover(r);
    log.line("## Crossover: fault-tolerant amplitude estimation against Monte Carlo (crossover.md, crossover.svg)");
    log.line("");
    log.line(x.markdown.substr(x.markdown.find("Assumptions:")));
  }
  // Panels for the README: the methods side by side, each 128 pixels wide.
  auto panel = [&](const std::string& out_name, const std::vector<std::string>& bases) {
    std::vector<qrm::io::image> imgs;
    for (const std::string& b : bases) {
      const qrm::io::image img = qrm::io::read_pfm(dir / (b + ".pfm"));
      imgs.push_back(img.width() >= 128 ? img
                     : img.width() <= 16 ? qrm::io::upsample_nearest(img, 128 / img.width())
                                         : qrm::io::upsample_nearest(img, std::max<std::size_t>(1, 128 / img.width())));
    }
    qrm::io::write_png(dir / out_name, qrm::io::side_by_side(imgs, 4, {0.2f, 0.2f, 0.2f}));
  };
  if (!quick) {
    const qrm::io::image est = qrm::io::read_pfm(dir / "paper_8x8_lightmap_estimated.pfm");
    qrm::io::write_pfm(dir / "paper_8x8_lightmap_upsampled.pfm", qrm::io::upsample_bilinear(est, 128, 128));
    panel("panel_lightmap.png", {"paper_8x8_lightmap_estimated", "paper_8x8_lightmap_exact",
                                 "paper_8x8_lightmap_classical", "paper_8x8_lightmap_upsampled"});
    panel("panel_cornell.png", {"cornell_box_8_exact", "cornell_box_8_mc", "cornell_box_8_emulated", "cornell_box_8_quantum"});
    panel("panel_spheres.png", {"two_spheres_8_exact", "two_spheres_8_mc", "two_spheres_8_emulated", "two_spheres_8_quantum"});
    panel("panel_cornell_64.png", {"cornell_box_64_exact", "cornell_box_64_mc", "cornell_box_64_emulated"});
    panel("panel_spheres_64.png", {"two_spheres_64_exact", "two_spheres_64_mc", "two_spheres_64_emulated"});
    panel("panel_quantum_32.png", {"cornell_box_32_exact", "cornell_box_32_quantum", "cornell_box_32_quantum_exact"});
  }
  log.line("Total: " + fmt(seconds_since(t_all), "%.1f") + " s.");
  qrm::io::write_file_atomically(dir / "summary.md", log.md);
  std::printf("%s", log.md.c_str());
  return 0;
}

}  // namespace qrm_cli
