// examples/qrm/render_job.hpp: what `qrm render` and `qrm figures` share: the render settings,
// the 2D light-map and 3D image jobs, their outputs (PNG for viewing, PFM for linear values,
// CSV/JSON for numbers), and tiles that `qrm merge` puts back together.
#pragma once

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <qrm/walk/directions.hpp>
#include <qrm/io/atomic_file.hpp>
#include <qrm/io/csv.hpp>
#include <qrm/io/image.hpp>
#include <qrm/io/pfm.hpp>
#include <qrm/io/png.hpp>
#include <qrm/io/progress.hpp>
#include <qrm/render/quantum.hpp>
#include <qrm/render/classical.hpp>
#include <qrm/render/voxelize.hpp>
#include <qrm/walk/model.hpp>

#include "args.hpp"
#include "commands.hpp"
#include "estimator_args.hpp"
#include "scene_arg.hpp"

namespace qrm_cli {

namespace fs = std::filesystem;

struct render_settings {
  std::string scene = "paper_8x8";
  unsigned width = 128, height = 128;  // 3D images
  unsigned voxels = 8;                 // 3D built-in scenes: N^3 voxels (default_voxels)
  std::optional<qrm::march_mode> march;  // --march; else the scene's, else surface
  unsigned directions = 0;             // 3D: 0 = by march (surface: 64, voxel: the authors' 15)
  int fractional_bits = -1;            // 3D: -1 = by march (surface: 4, voxel: the authors' 3)
  unsigned steps = 0;                  // 0: 3 in 2D (the paper), 6 in 3D
  std::size_t paths = 32;              // 3D: paths per pixel (emulated, Monte Carlo)
  std::string methods = "all";         // 3D: exact, mc, emulated, quantum, all (= exact,mc,emulated)
  qrm::estimator_settings estimator;   // default FAE, maxiter 5, rescaling
  json_object estimator_json;          // the estimator and its options, for summaries
  // simulated: every Grover iteration applied to the state; analytic: P(out=1) read once from
  // the simulated state, then the sin^2 law (the same measurement statistics, tested). Default:
  // simulated for 2D light maps, analytic for 3D images (one 3D walk state takes ~30 ms).
  std::string grover = "auto";
  qrm::render::grover_mode grover_for(unsigned dims) const {
    if (grover == "simulated" || (grover == "auto" && dims == 2)) return qrm::render::grover_mode::simulated;
    return qrm::render::grover_mode::analytic;
  }
  // --noise: 2D light maps estimated on a noisy quantum computer (quantum trajectories).
  std::optional<qrm::noise_model> noise;
  std::string noise_text;               // as given, for the summary
  std::size_t trajectories = 20;
  qrm::noise_level noise_level = qrm::noise_level::logical;
  std::uint64_t seed = 1;
  std::string out = "out";
  qrm::render::tile part{};
  unsigned threads = 0;
  qrm::io::progress_options progress;  // --quiet, --progress
  float exposure = 1.0f;

  unsigned effective_steps(unsigned dims) const { return steps ? steps : (dims == 2 ? 3u : 6u); }
  qrm::march_mode march_for(const qrm::scene& sc) const { return qrm_cli::march_for(march, sc); }
  // 3D direction sets: for the surface march a golden spiral of 64 directions (a full 6-qubit
  // register; 26 king moves leave whole walls dark between their 45-degree light footprints)
  // with 4 sub-voxel bits (displacements round(16 v): each ray within about 2 degrees of its
  // direction); for the voxel march the authors' 15 directions and 3 sub-voxel bits.
  // A run that includes the fully quantum method uses the 14 cube directions (2 sub-voxel bits)
  // for every method it renders: the walk state's support grows as (D / 2)^s, and 128x128 pixels
  // of the 32^3 box at s = 6 take about a minute with 14 directions, hours with 64.
  unsigned directions_for(const qrm::scene& sc) const {
    if (directions) return directions;
    if (march_for(sc) == qrm::march_mode::voxel) return 15u;
    return quantum_run() ? 14u : 64u;
  }
  unsigned fractional_bits_for(const qrm::scene& sc) const {
    if (fractional_bits >= 0) return static_cast<unsigned>(fractional_bits);
    if (march_for(sc) == qrm::march_mode::voxel) return 3u;
    return quantum_run() ? 2u : 4u;
  }
  bool quantum_run() const;
  bool tiled() const { return part.count > 1; }
};

inline qrm::render::tile parse_tile(const std::string& v) {
  const auto slash = v.find('/');
  auto bad = [&] { return usage_error("--tile must be i/n with 0 <= i < n (e.g. 0/4), got '" + v + "'"); };
  if (slash == std::string::npos) throw bad();
  try {
    std::size_t used = 0;
    const long i = std::stol(v.substr(0, slash), &used);
    if (used != slash) throw bad();
    const std::string rest = v.substr(slash + 1);
    const long n = std::stol(rest, &used);
    if (used != rest.size() || n < 1 || i < 0 || i >= n || n > 100000) throw bad();
    return {static_cast<unsigned>(i), static_cast<unsigned>(n)};
  } catch (const std::logic_error&) {
    throw bad();
  }
}

// --noise depolarizing:P1[,P2] | superconducting | ion (P2 = P1 when not given).
inline qrm::noise_model parse_noise_flag(const std::string& v) {
  if (v == "superconducting" || v == "ion") return qrm::noise_preset(v);
  const std::string prefix = "depolarizing:";
  auto bad = [&] {
    return usage_error("--noise must be depolarizing:P1[,P2] (error rates in [0, 1]), superconducting or ion; got '" +
                       v + "'");
  };
  if (v.rfind(prefix, 0) != 0) throw bad();
  const auto p = number_list(v.substr(prefix.size()));
  if (!p || p->size() > 2) throw bad();
  for (double x : *p)
    if (!(x >= 0 && x <= 1)) throw bad();
  return qrm::depolarizing_noise((*p)[0], p->size() == 2 ? (*p)[1] : (*p)[0]);
}

// A built-in 3D scene's size without --voxels: the paper's 8^3, except where a sphere must be a
// mirror or a glossy ball rather than a few voxels (at 8^3 the 110 mm sphere is two voxels
// across; at 32^3 it is eight, and its reflection of the red wall is recognisable).
inline unsigned default_voxels(const std::string& scene) {
  return scene == "cornell_mirror" || scene == "cornell_glossy" ? 32 : 8;
}

inline render_settings parse_render_settings(args& a) {
  render_settings s;
  s.scene = a.str("scene", s.scene);
  s.width = static_cast<unsigned>(a.integer("width", s.width, 1, 8192));
  s.height = static_cast<unsigned>(a.integer("height", s.height, 1, 8192));
  s.voxels = static_cast<unsigned>(a.integer("voxels", default_voxels(s.scene), 4, 256));
  if ((s.voxels & (s.voxels - 1)) != 0)
    throw usage_error("--voxels must be a power of two (the walk's position registers), got " + a.str("voxels", ""));
  s.march = march_flag(a);
  if (a.has("directions")) s.directions = static_cast<unsigned>(a.integer("directions", 26, 6, 256));
  if (a.has("fractional-bits")) s.fractional_bits = static_cast<int>(a.integer("fractional-bits", 0, 0, 8));
  s.steps = static_cast<unsigned>(a.integer("steps", 0, 1, 16));
  s.paths = static_cast<std::size_t>(a.integer("paths", 32, 1, 1 << 24));
  s.methods = a.str("method", s.methods);
  {
    std::stringstream ss(s.methods);
    for (std::string m; std::getline(ss, m, ',');)
      if (m != "exact" && m != "mc" && m != "emulated" && m != "quantum" && m != "all")
        throw usage_error("--method must be a comma-separated list of exact, mc, emulated, quantum or all; got '" + m +
                          "'");
  }
  s.grover = a.str("grover", "auto");
  if (s.grover != "auto" && s.grover != "simulated" && s.grover != "analytic")
    throw usage_error("--grover must be simulated, analytic or auto, got '" + s.grover + "'");
  if (a.has("noise")) {
    s.noise_text = a.str("noise", "");
    s.noise = parse_noise_flag(s.noise_text);
  }
  s.trajectories = static_cast<std::size_t>(a.integer("trajectories", 20, 1, 1000000));
  const std::string level = a.str("noise-level", "logical");
  if (level != "logical" && level != "gates" && level != "global")
    throw usage_error("--noise-level must be logical, gates or global, got '" + level + "'");
  s.noise_level = level == "gates"    ? qrm::noise_level::gates
                  : level == "global" ? qrm::noise_level::global
                                      : qrm::noise_level::logical;
  s.seed = static_cast<std::uint64_t>(a.integer("seed", 1, 0, std::numeric_limits<std::int64_t>::max()));
  s.out = a.str("out", s.out);
  if (a.has("tile")) s.part = parse_tile(a.str("tile", ""));
  s.threads = static_cast<unsigned>(a.integer("threads", 0, 0, 1024));
  s.progress = progress_from_flags(a);
  s.exposure = static_cast<float>(a.number("exposure", 1.0));
  if (!(s.exposure > 0)) throw usage_error("--exposure must be positive, got " + a.str("exposure", ""));
  const parsed_estimator e = parse_estimator_args(a, "", "fae", "ae-steps");
  s.estimator = e.settings;
  s.estimator_json = e.json();
  return s;
}

inline bool wants(const render_settings& s, const std::string& method) {
  std::stringstream ss(s.methods);
  for (std::string m; std::getline(ss, m, ',');)
    if (m == method || (m == "all" && method != "quantum")) return true;
  return false;
}
inline bool render_settings::quantum_run() const { return wants(*this, "quantum"); }

// The built-in 3D scenes, sized by --voxels.
inline bool builtin_3d_scene(const std::string& name) {
  return name == "cornell" || name == "spheres" || name == "cornell_mirror" || name == "cornell_glossy" ||
         name == "cornell_fog";
}

// The scene a --scene value names: built-in 2D scenes, the 3D Cornell box, two spheres, the
// Cornell box with a mirror or a glossy sphere or with fog (at --voxels), or a scene file.
inline qrm::scene load_render_scene(const render_settings& s) {
  if (s.scene == "cornell") return qrm::render::cornell_box(s.voxels);
  if (s.scene == "spheres") return qrm::render::two_spheres(s.voxels);
  if (s.scene == "cornell_mirror") return qrm::render::cornell_mirror(s.voxels);
  if (s.scene == "cornell_glossy") return qrm::render::cornell_glossy(s.voxels, 2.0);
  if (s.scene == "cornell_fog") return qrm::render::cornell_fog(s.voxels);
  return scene_from_arg(s.scene, "paper_4x4, paper_8x8, cornell, spheres, cornell_mirror, cornell_glossy, cornell_fog");
}

// Flags that do not apply to the scene or the methods chosen are errors, never silently ignored.
inline void check_render_flags_apply(const args& a, const render_settings& s, const qrm::scene& sc) {
  const std::string scene = "--scene " + s.scene;
  for (const char* f : {"trajectories", "noise-level"})
    if (a.has(f) && !a.has("noise")) throw usage_error(std::string("--") + f + " applies with --noise; give --noise");
  if (a.has("noise") && sc.dims() == 3)
    throw usage_error("--noise applies to 2D light maps (one noisy amplitude estimate per cell and channel); " + scene +
                      " is 3D");
  if (a.has("noise") && s.grover == "analytic")
    throw usage_error("--noise runs the noisy circuit as quantum trajectories; --grover analytic reads the ideal state");
  if (sc.dims() == 2) {
    for (const char* f : {"width", "height", "voxels", "directions", "fractional-bits", "paths", "method"})
      if (a.has(f))
        throw usage_error(std::string("--") + f + " applies to 3D scenes; " + scene +
                          " is a 2D light map (one amplitude estimate per cell and channel)");
    return;
  }
  if (a.has("voxels") && !builtin_3d_scene(s.scene))
    throw usage_error("--voxels sets the size of the built-in 3D scenes (cornell, spheres, cornell_mirror, "
                      "cornell_glossy, cornell_fog); the scene file " +
                      s.scene + " has its own size (" + std::to_string(sc.size()) + ")");
  const bool sampled = wants(s, "mc") || wants(s, "emulated");
  const bool estimated = wants(s, "emulated") || wants(s, "quantum");
  if (a.has("paths") && !sampled)
    throw usage_error("--paths applies to --method mc and emulated; --method " + s.methods + " samples no paths");
  if (a.has("grover") && !wants(s, "quantum"))
    throw usage_error("--grover applies to 2D light maps and --method quantum; --method " + s.methods +
                      " runs no walk circuit");
  if (!estimated)
    for (const flag& f : estimator_flag_table("ae-steps"))
      if (a.has(f.name))
        throw usage_error(std::string("--") + f.name + " applies to --method emulated and quantum (amplitude " +
                          "estimation); --method " + s.methods + " estimates no amplitudes");
}

// A progress bar per renderer call, created on the first report (the renderer knows the total:
// distinct walk starts or pixels), with rate and ETA; reports come from any thread.
class job_progress {
 public:
  job_progress(std::string label, qrm::io::progress_options o) : label_(std::move(label)), options_(o) {}
  std::function<void(std::size_t, std::size_t)> callback() {
    return [this](std::size_t finished, std::size_t total) {
      std::call_once(started_, [&] { bar_.emplace(label_, total, options_); });
      bar_->advance(finished);
    };
  }
  void finish() {
    if (bar_) bar_->finish();
  }

 private:
  std::string label_;
  qrm::io::progress_options options_;
  std::once_flag started_;
  std::optional<qrm::io::progress> bar_;
};

// ---- outputs ----------------------------------------------------------------------------------

inline std::string tile_suffix(const render_settings& s) {
  return s.tiled() ? ".part-" + std::to_string(s.part.index) + "-of-" + std::to_string(s.part.count) : std::string();
}

// An image result: the PFM (linear values) always; a PNG for viewing unless this is a tile
// (tiles are merged first). `block` enlarges small maps with visible cells.
inline void write_image(const render_settings& s, const std::string& base, const qrm::io::image& img,
                        std::vector<std::string>& written, std::size_t block = 1) {
  const fs::path dir(s.out);
  qrm::io::write_pfm(dir / (base + tile_suffix(s) + ".pfm"), img);
  written.push_back(base + tile_suffix(s) + ".pfm");
  if (s.tiled()) return;
  qrm::io::tone_map tm;
  tm.exposure = s.exposure;
  const qrm::io::image shown = block > 1 ? qrm::io::upsample_nearest(img, block) : img;
  qrm::io::write_png(dir / (base + ".png"), shown, tm);
  written.push_back(base + ".png");
}

// A tile's manifest: the command line that made it, and the tile (qrm merge reads it back).
inline void write_manifest(const render_settings& s, const std::string& kind, const std::vector<std::string>& bases,
                           const json_object& settings) {
  json_object j;
  j.add("kind", kind).add("tile", s.part.index).add("tiles", s.part.count).add("settings", settings);
  j.add("images", json_array::of(bases));
  qrm::io::write_file_atomically(fs::path(s.out) / ("manifest" + tile_suffix(s) + ".json"), j.str() + "\n");
}

inline json_object settings_json(const render_settings& s, const qrm::scene& sc, unsigned steps) {
  json_object j;
  j.add("scene", sc.name()).add("dims", sc.dims()).add("size", sc.size()).add("steps", steps).add("seed", s.seed);
  if (sc.dims() == 3) {
    j.add("width", s.width).add("height", s.height).add("directions", s.directions_for(sc));
    j.add("fractional_bits", s.fractional_bits_for(sc)).add("paths", s.paths).add("methods", s.methods);
  }
  j.add("march", qrm::march_name(s.march_for(sc)));
  j.add("grover", s.grover_for(sc.dims()) == qrm::render::grover_mode::simulated ? "simulated" : "analytic");
  if (s.noise) {
    j.add("noise", s.noise_text).add("trajectories", s.trajectories);
    j.add("noise_level", s.noise_level == qrm::noise_level::gates    ? "gates"
                         : s.noise_level == qrm::noise_level::global ? "global"
                                                                     : "logical");
  }
  return j.add("estimator", s.estimator_json);
}

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// ---- 2D: the light map (the paper's Fig. 4) -----------------------------------------------

struct lightmap_summary {
  std::size_t cell_channels = 0, inside_interval = 0;
  double rmse_vs_exact = 0, rmse_vs_classical = 0, max_interference = 0;
  std::uint64_t a_calls = 0;
  double seconds = 0;
  std::vector<std::string> written;
};

// The difference and upsampled images (after merging, for tiled renders).
inline void write_lightmap_figures(const render_settings& s, const std::string& base,
                                   const qrm::render::lightmap_images& maps, std::vector<std::string>& written) {
  const fs::path dir(s.out);
  const std::size_t block = std::max<std::size_t>(1, 256 / maps.estimated.width());
  const qrm::io::image diff = qrm::io::absolute_difference(maps.estimated, maps.classical);
  qrm::io::write_pfm(dir / (base + "_difference.pfm"), diff);
  qrm::io::write_png(dir / (base + "_difference.png"), qrm::io::upsample_nearest(qrm::io::false_colour(diff), block));
  qrm::io::tone_map tm;
  tm.exposure = s.exposure;
  const qrm::io::image up =
      qrm::io::upsample_bilinear(maps.estimated, 256, 256 * maps.estimated.height() / maps.estimated.width());
  qrm::io::write_pfm(dir / (base + "_upsampled.pfm"), up);
  qrm::io::write_png(dir / (base + "_upsampled.png"), up, tm);
  written.push_back(base + "_difference.pfm");
  written.push_back(base + "_difference.png");
  written.push_back(base + "_upsampled.pfm");
  written.push_back(base + "_upsampled.png");
}

inline lightmap_summary render_lightmap(const render_settings& s, const qrm::scene& sc) {
  const unsigned steps = s.effective_steps(2);
  const qrm::walk_model model(sc, qrm::king_2d(), s.march_for(sc));
  qrm::render::quantum_options o;
  o.steps = steps;
  o.estimator = s.estimator;
  o.grover = s.grover_for(2);
  o.noise = s.noise;
  o.noisy.trajectories = s.trajectories;
  o.noisy.level = s.noise_level;
  o.seed = s.seed;
  o.threads = s.threads;
  o.part = s.part;
  const auto range = qrm::render::tile_pixels(sc.voxel_count(), s.part);
  const qrm::io::progress_options po = s.progress;
  qrm::io::progress bar("light map " + sc.name(), (range.end - range.begin) * 3, po);
  o.progress = [&](std::size_t finished, std::size_t) { bar.advance(finished); };
  const auto t0 = std::chrono::steady_clock::now();
  const auto cells = qrm::render::estimate_lightmap(model, o);
  lightmap_summary out;
  out.seconds = seconds_since(t0);
  bar.finish();

  qrm::io::table t({"scene", "x", "y", "channel", "estimate", "interval_lo", "interval_hi", "exact", "classical",
                    "radiance_scale", "a_calls", "grover_calls"});
  double se = 0, sc2 = 0;
  for (const auto& q : cells) {
    if (!q.computed) continue;
    const auto xy = sc.coords(q.index);
    t.add_row({sc.name(), xy[0], xy[1], q.channel, q.estimate, q.interval[0], q.interval[1], q.exact, q.classical,
               q.radiance_scale, q.a_calls, q.grover_calls});
    ++out.cell_channels;
    out.inside_interval += q.exact >= q.interval[0] && q.exact <= q.interval[1];
    se += std::pow((q.estimate - q.exact) * q.radiance_scale, 2);
    sc2 += std::pow((q.estimate - q.classical) * q.radiance_scale, 2);
    if (q.classical > 0) out.max_interference = std::max(out.max_interference, std::abs(q.exact - q.classical) / q.classical);
    out.a_calls += q.a_calls;
  }
  out.rmse_vs_exact = std::sqrt(se / std::max<std::size_t>(1, out.cell_channels));
  out.rmse_vs_classical = std::sqrt(sc2 / std::max<std::size_t>(1, out.cell_channels));
  const fs::path dir(s.out);
  const std::string base = sc.name() + "_lightmap";
  qrm::io::write_csv(dir / (base + tile_suffix(s) + ".csv"), t);
  out.written.push_back(base + tile_suffix(s) + ".csv");
  const auto maps = qrm::render::lightmap_as_images(sc, cells);
  const std::size_t block = std::max<std::size_t>(1, 256 / sc.size());
  write_image(s, base + "_estimated", maps.estimated, out.written, block);
  write_image(s, base + "_exact", maps.exact, out.written, block);
  write_image(s, base + "_classical", maps.classical, out.written, block);
  if (s.tiled()) {
    write_manifest(s, "lightmap", {base + "_estimated", base + "_exact", base + "_classical"}, settings_json(s, sc, steps));
  } else {
    write_lightmap_figures(s, base, maps, out.written);
  }
  return out;
}

// ---- 3D images -------------------------------------------------------------------------------

struct image3d_summary {
  std::map<std::string, double> seconds, rmse_vs_exact;
  std::size_t distinct_starts = 0;
  // Fully quantum: per (start, channel), the exact P(out = 1) inside the estimator's interval,
  // and the largest relative difference between the faithful (interfering) walk and the
  // classical path sum (interference, as in the 2D light map).
  std::size_t start_channels = 0, inside_interval = 0;
  double max_interference = 0;
  // Per simulated (start, channel): the circuit's qubits, the final state's nonzero amplitudes,
  // the seconds to build and simulate it once.
  std::size_t qubits_max = 0, nonzeros_max = 0;
  double qubits_mean = 0, nonzeros_mean = 0, seconds_per_start = 0;
  std::vector<std::string> written;
};

// The camera a 3D scene is seen through: its file's camera block, else the Cornell box's.
inline qrm::render::camera scene_camera(const render_settings& s, const qrm::scene& sc) {
  if (const auto& v = sc.view())
    return qrm::render::camera(v->position, v->look_at, v->up, v->vertical_fov_degrees, s.width, s.height);
  if (sc.size() < 8)
    throw usage_error("--scene " + s.scene + " is " + std::to_string(sc.size()) +
                      "^3 voxels and has no camera block; the default (Cornell box) camera needs at least 8^3. "
                      "Add a line 'camera position X Y Z look_at X Y Z' (README: scene files)");
  return qrm::render::box_scene_camera(sc.size(), s.width, s.height);
}

// The flags that name the walk an analysis command (crossover, resources) studies, and their
// parsing: --scene, --voxels, --x, --y, --width, --height, --march.
inline void add_walk_target_flags(flag_table& f, const char* group) {
  const flag rows[] = {
      {"scene", "NAME|FILE", "paper_8x8",
       "paper_4x4, paper_8x8 (2D), cornell, spheres, cornell_mirror, cornell_glossy, cornell_fog (3D) or a scene file",
       group},
      {"voxels", "N", "8; 32 for cornell_mirror and cornell_glossy",
       "the built-in 3D scenes: N^3 voxels, a power of two in 4..256", group},
      {"x", "X", "3 (3D: width / 2)", "2D: the cell's column; 3D: the pixel's column", group},
      {"y", "Y", "4 (3D: height / 2)", "2D: the cell's row; 3D: the pixel's row", group},
      {"width", "N", "32", "3D: the image the pixel belongs to (1..1024), walked as qrm render --method quantum", group},
      {"height", "N", "32", "3D: the image the pixel belongs to (1..1024)", group},
      march_flag_row(group),
  };
  for (const flag& r : rows) f.push_back(r);
}
struct walk_target {
  render_settings view;  // scene name, voxels, width and height as parsed
  qrm::scene scene;
  unsigned x = 3, y = 4;
  std::optional<qrm::march_mode> march;
  bool three_d() const { return scene.dims() == 3; }
};
inline walk_target walk_target_from_flags(const args& a) {
  walk_target t;
  t.view.scene = a.str("scene", "paper_8x8");
  t.view.voxels = static_cast<unsigned>(a.integer("voxels", default_voxels(t.view.scene), 4, 256));
  if ((t.view.voxels & (t.view.voxels - 1)) != 0)
    throw usage_error("--voxels must be a power of two (the walk's position registers), got " + a.str("voxels", ""));
  t.scene = load_render_scene(t.view);
  if (!t.three_d())
    for (const char* f : {"voxels", "width", "height"})
      if (a.has(f)) throw usage_error(std::string("--") + f + " applies to 3D scenes; --scene " + t.view.scene + " is 2D");
  if (a.has("voxels") && !builtin_3d_scene(t.view.scene))
    throw usage_error("--voxels sets the size of the built-in 3D scenes, not of the scene file " + t.view.scene);
  t.view.width = static_cast<unsigned>(a.integer("width", 32, 1, 1024));
  t.view.height = static_cast<unsigned>(a.integer("height", 32, 1, 1024));
  const bool d3 = t.three_d();
  const auto nx = static_cast<std::int64_t>(d3 ? t.view.width : t.scene.size()) - 1;
  const auto ny = static_cast<std::int64_t>(d3 ? t.view.height : t.scene.size()) - 1;
  t.x = static_cast<unsigned>(a.integer("x", d3 ? t.view.width / 2 : 3, 0, nx));
  t.y = static_cast<unsigned>(a.integer("y", d3 ? t.view.height / 2 : 4, 0, ny));
  t.march = march_flag(a);
  return t;
}

// The one walk an analysis command (crossover, resources) studies: light-map cell (x, y) of a 2D
// scene, or, in 3D, the first hit of pixel (x, y) of a width x height image through the scene's
// camera, walked as qrm render --method quantum walks it (its march, directions and sub-voxel
// bits). A pixel that sees no voxel is a usage error naming it.
struct studied_walk {
  qrm::walk_model model;
  qrm::walk_start start;
  std::string where;  // "cell (3, 4)" or "pixel (16, 16) of a 32x32 image"
};
inline studied_walk study_walk(const qrm::scene& sc, std::optional<qrm::march_mode> march, unsigned x, unsigned y,
                               unsigned width, unsigned height) {
  const bool three_d = sc.dims() == 3;
  render_settings rs;
  rs.scene = sc.name();
  rs.width = width;
  rs.height = height;
  rs.methods = "quantum";
  rs.march = march_for(march, sc);
  studied_walk w{qrm::walk_model(sc,
                                 three_d ? qrm::sphere_directions(rs.directions_for(sc), rs.fractional_bits_for(sc))
                                         : qrm::king_2d(),
                                 *rs.march),
                 {},
                 (three_d ? "pixel (" : "cell (") + std::to_string(x) + ", " + std::to_string(y) + ")"};
  if (!three_d) {
    w.start = w.model.light_map_start({x, y, 0});
    return w;
  }
  const auto px = qrm::render::pixel_starts(w.model, scene_camera(rs, sc));
  const qrm::render::pixel_start& hit = px[static_cast<std::size_t>(y) * width + x];
  w.where += " of a " + std::to_string(width) + "x" + std::to_string(height) + " image";
  if (!hit.hit) throw usage_error(w.where + " of " + sc.name() + " sees no voxel");
  w.start = qrm::detail::render_start_of(sc, {hit.voxel, hit.start.direction});
  return w;
}

inline image3d_summary render_images_3d(const render_settings& s, const qrm::scene& sc) {
  const unsigned steps = s.effective_steps(3);
  const qrm::walk_model model(sc, qrm::sphere_directions(s.directions_for(sc), s.fractional_bits_for(sc)),
                              s.march_for(sc));
  const qrm::render::camera cam = scene_camera(s, sc);
  qrm::render::render_options ro;
  ro.steps = steps;
  ro.threads = s.threads;
  ro.part = s.part;
  image3d_summary out;
  const std::string base = sc.name();
  std::vector<std::string> bases;
  std::vector<std::string> wanted;
  for (const char* m : {"exact", "mc", "emulated", "quantum"})
    if (wants(s, m)) wanted.push_back(m);
  const qrm::io::progress_options po = s.progress;
  qrm::io::image exact;
  for (const std::string& m : wanted) {
    const auto t0 = std::chrono::steady_clock::now();
    job_progress bar("render " + base + " " + m, po);
    ro.progress = bar.callback();
    qrm::io::image img;
    if (m == "exact") {
      img = exact = qrm::render::render_exact(model, cam, ro);
    } else if (m == "mc") {
      const auto mc = qrm::render::render_monte_carlo(model, cam, s.paths, s.seed, ro);
      img = mc.mean;
      write_image(s, base + "_mc_standard_error", mc.standard_error, out.written);
      bases.push_back(base + "_mc_standard_error");
    } else if (m == "emulated") {
      qrm::render::emulation_options e;
      e.paths_per_pixel = s.paths;
      e.seed = s.seed;
      e.estimate = qrm::render::amplitude_path_estimator(s.estimator);
      img = qrm::render::render_emulated(model, cam, e, ro).sampled;
    } else {
      qrm::render::quantum_options q;
      q.steps = steps;
      q.estimator = s.estimator;
      q.grover = s.grover_for(3);
      q.seed = s.seed;
      q.threads = s.threads;
      q.part = s.part;
      q.progress = ro.progress;
      const auto qi = qrm::render::render_quantum(model, cam, q);
      img = qi.estimated;
      out.distinct_starts = qi.distinct_starts;
      for (const auto& e : qi.starts) {
        if (!e.computed) continue;
        ++out.start_channels;
        out.inside_interval += e.exact >= e.interval[0] && e.exact <= e.interval[1];
        if (e.classical > 0) out.max_interference = std::max(out.max_interference, std::abs(e.exact - e.classical) / e.classical);
        out.qubits_max = std::max(out.qubits_max, e.qubits);
        out.nonzeros_max = std::max(out.nonzeros_max, e.nonzeros);
        out.qubits_mean += static_cast<double>(e.qubits);
        out.nonzeros_mean += static_cast<double>(e.nonzeros);
        out.seconds_per_start += e.simulate_seconds;
      }
      if (out.start_channels) {
        const double n = static_cast<double>(out.start_channels);
        out.qubits_mean /= n;
        out.nonzeros_mean /= n;
        out.seconds_per_start /= n;
      }
      write_image(s, base + "_quantum_exact", qi.exact, out.written);
      bases.push_back(base + "_quantum_exact");
    }
    out.seconds[m] = seconds_since(t0);
    write_image(s, base + "_" + m, img, out.written);
    bases.push_back(base + "_" + m);
    if (!exact.empty() && m != "exact" && !s.tiled()) out.rmse_vs_exact[m] = qrm::io::rmse(img, exact);
    bar.finish();
  }
  if (s.tiled()) write_manifest(s, "images", bases, settings_json(s, sc, steps));
  return out;
}

}  // namespace qrm_cli
