// qrm render: the paper's images. A 2D scene gives its light map (Fig. 4): the faithful circuit
// per cell and channel, estimated with an amplitude estimator (default FAE, maxiter 5, with
// rescaling, as the paper) on the fully simulated circuit, next to the exact and classical maps.
// A 3D scene (cornell, spheres, cornell_mirror, cornell_glossy, cornell_fog, or a file) gives images by the exact path sum, Monte Carlo path
// tracing, the paper's emulator (K sampled paths + amplitude estimation) and, on request, the
// fully quantum walk circuit per pixel.
#include <cstdio>
#include <string>

#include "commands.hpp"
#include "render_job.hpp"

namespace qrm_cli {

flag_table render_flags() {
  const char* scene = "scene";
  const char* img = "3D images";
  const char* run = "run and output";
  flag_table f = {
      {"scene", "NAME|FILE", "paper_8x8", "paper_4x4, paper_8x8 (2D light maps), cornell, spheres, cornell_mirror (a mirror sphere), cornell_glossy (a glossy one, lobe 2), cornell_fog (thin fog in the room) (3D), or a scene file", scene},
      {"voxels", "N", "8; 32 for cornell_mirror and cornell_glossy", "cornell, spheres, cornell_mirror, cornell_glossy, cornell_fog: N^3 voxels, a power of two in 4..256", scene},
      {"steps", "S", "3 in 2D, 6 in 3D", "walk steps (1..16): voxels crossed (voxel march) or bounces (surface)", scene},
      march_flag_row(scene),
      {"width", "N", "128", "image width in pixels (1..8192)", img},
      {"height", "N", "128", "image height in pixels (1..8192)", img},
      {"directions", "D", "64 (surface; 14 with --method quantum), 15 (voxel)", "directions, 6..256: 6, 14, 26 = the symmetric cube sets, any other D = a golden spiral (the authors used 15)", img},
      {"fractional-bits", "F", "4 (surface; 2 with quantum), 3 (voxel)", "sub-voxel position bits (0..8; the authors used 3); 0 with a cube set moves whole voxels (king moves)", img},
      {"method", "LIST", "all", "comma-separated: exact, mc, emulated, quantum; all = exact,mc,emulated", img},
      {"paths", "K", "32", "paths per pixel for mc and emulated (the paper's 32)", img},
      {"grover", "auto|simulated|analytic", "auto",
       "apply every Grover iteration to the state, or read P(out=1) once and use the sin^2 law; "
       "auto: simulated in 2D, analytic in 3D",
       img},
      {"noise", "depolarizing:P1[,P2]|superconducting|ion", "",
       "2D: estimate on a noisy quantum computer (P1 per single-qubit gate, P2 per CNOT; presets in "
       "include/qrm/noise/model.hpp), as quantum trajectories",
       img},
      {"trajectories", "N", "20", "with --noise: quantum trajectories per cell and channel", img},
      {"noise-level", "logical|gates|global", "logical",
       "with --noise: trajectories with one Pauli channel per logical op (rate from its decomposition), or with noise "
       "on every gate of the decomposed circuit (slow); global: no trajectories, each run of A or Q fully "
       "depolarizes with its decomposition's error probability (closed form, any size)",
       img},
      {"out", "DIR", "out", "output directory (created)", run},
      {"tile", "I/N", "", "render only tile I of N (0 <= I < N); put the tiles together with qrm merge", run},
      {"seed", "S", "1", "random seed (integer >= 0); pixel p uses stream (S, p)", run},
      {"threads", "T", "0", "worker threads; 0 = all cores (the result does not depend on it)", run},
      {"exposure", "X", "1", "multiply radiance by X before tone mapping the PNGs", run},
  };
  add_progress_flags(f, run);
  for (const flag& e : estimator_flag_table("ae-steps")) f.push_back(e);
  return f;
}

int cmd_render(args& a) {
  a.allow(render_flags());
  const render_settings s = parse_render_settings(a);
  const qrm::scene sc = load_render_scene(s);
  check_render_flags_apply(a, s, sc);
  if (sc.dims() == 3) (void)scene_camera(s, sc);  // refuse a scene the camera cannot see before creating anything
  qrm::io::ensure_directory(s.out);
  json_object summary;
  summary.add("scene", sc.name());
  if (sc.dims() == 2) {
    const auto r = render_lightmap(s, sc);
    summary.add("kind", "lightmap").add("cell_channels", r.cell_channels).add("exact_inside_interval", r.inside_interval);
    summary.add("rmse_vs_exact", r.rmse_vs_exact).add("rmse_vs_classical", r.rmse_vs_classical);
    summary.add("max_relative_interference", r.max_interference).add("oracle_calls", r.a_calls);
    summary.add("seconds", r.seconds).add("settings", settings_json(s, sc, s.effective_steps(2)));
  } else {
    const auto r = render_images_3d(s, sc);
    json_object seconds, rmse;
    for (const auto& [m, t] : r.seconds) seconds.add(m, t);
    for (const auto& [m, v] : r.rmse_vs_exact) rmse.add(m, v);
    summary.add("kind", "images").add("seconds", seconds).add("rmse_vs_exact", rmse);
    if (wants(s, "quantum"))
      summary.add("distinct_starts", r.distinct_starts).add("start_channels", r.start_channels)
          .add("exact_inside_interval", r.inside_interval).add("max_relative_interference", r.max_interference)
          .add("qubits_mean", r.qubits_mean).add("qubits_max", r.qubits_max).add("nonzeros_mean", r.nonzeros_mean)
          .add("nonzeros_max", r.nonzeros_max).add("simulate_seconds_per_start", r.seconds_per_start);
    summary.add("settings", settings_json(s, sc, s.effective_steps(3)));
  }
  const std::string text = summary.str();
  if (!s.tiled()) qrm::io::write_file_atomically(fs::path(s.out) / (sc.name() + "_summary.json"), text + "\n");
  std::printf("%s\n", text.c_str());
  return 0;
}

}  // namespace qrm_cli
