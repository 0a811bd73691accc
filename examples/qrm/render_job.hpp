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

qrm::render::tile parse_tile(const std::string& v);

// --noise depolarizing:P1[,P2] | superconducting | ion (P2 = P1 when not given).
qrm::noise_model parse_noise_flag(const std::string& v);

// A built-in 3D scene's size without --voxels: the paper's 8^3, except where a sphere must be a
// mirror or a glossy ball rather than a few voxels (at 8^3 the 110 mm sphere is two voxels
// across; at 32^3 it is eight, and its reflection of the red wall is recognisable).
unsigned default_voxels(const std::string& scene);

render_settings parse_render_settings(args& a);

bool wants(const render_settings& s, const std::string& method);

// The built-in 3D scenes, sized by --voxels.
bool builtin_3d_scene(const std::string& name);

// The scene a --scene value names: built-in 2D scenes, the 3D Cornell box, two spheres, the
// Cornell box with a mirror or a glossy sphere or with fog (at --voxels), or a scene file.
qrm::scene load_render_scene(const render_settings& s);

// Flags that do not apply to the scene or the methods chosen are errors, never silently ignored.
void check_render_flags_apply(const args& a, const render_settings& s, const qrm::scene& sc);

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

std::string tile_suffix(const render_settings& s);

// An image result: the PFM (linear values) always; a PNG for viewing unless this is a tile
// (tiles are merged first). `block` enlarges small maps with visible cells.
void write_image(const render_settings& s, const std::string& base, const qrm::io::image& img,
                        std::vector<std::string>& written, std::size_t block = 1);

// A tile's manifest: the command line that made it, and the tile (qrm merge reads it back).
void write_manifest(const render_settings& s, const std::string& kind, const std::vector<std::string>& bases,
                           const json_object& settings);

json_object settings_json(const render_settings& s, const qrm::scene& sc, unsigned steps);

double seconds_since(std::chrono::steady_clock::time_point t0);

// ---- 2D: the light map (the paper's Fig. 4) -----------------------------------------------

struct lightmap_summary {
  std::size_t cell_channels = 0, inside_interval = 0;
  double rmse_vs_exact = 0, rmse_vs_classical = 0, max_interference = 0;
  std::uint64_t a_calls = 0;
  double seconds = 0;
  std::vector<std::string> written;
};

// The difference and upsampled images (after merging, for tiled renders).
void write_lightmap_figures(const render_settings& s, const std::string& base,
                                   const qrm::render::lightmap_images& maps, std::vector<std::string>& written);

lightmap_summary render_lightmap(const render_settings& s, const qrm::scene& sc);

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
qrm::render::camera scene_camera(const render_settings& s, const qrm::scene& sc);

// The flags that name the walk an analysis command (crossover, resources) studies, and their
// parsing: --scene, --voxels, --x, --y, --width, --height, --march.
void add_walk_target_flags(flag_table& f, const char* group);
struct walk_target {
  render_settings view;  // scene name, voxels, width and height as parsed
  qrm::scene scene;
  unsigned x = 3, y = 4;
  std::optional<qrm::march_mode> march;
  bool three_d() const { return scene.dims() == 3; }
};
walk_target walk_target_from_flags(const args& a);

// The one walk an analysis command (crossover, resources) studies: light-map cell (x, y) of a 2D
// scene, or, in 3D, the first hit of pixel (x, y) of a width x height image through the scene's
// camera, walked as qrm render --method quantum walks it (its march, directions and sub-voxel
// bits). A pixel that sees no voxel is a usage error naming it.
struct studied_walk {
  qrm::walk_model model;
  qrm::walk_start start;
  std::string where;  // "cell (3, 4)" or "pixel (16, 16) of a 32x32 image"
};
studied_walk study_walk(const qrm::scene& sc, std::optional<qrm::march_mode> march, unsigned x, unsigned y,
                               unsigned width, unsigned height);

image3d_summary render_images_3d(const render_settings& s, const qrm::scene& sc);

}  // namespace qrm_cli
