// qrm render: the paper's images. A 2D scene gives its light map (Fig. 4): the faithful circuit
// per cell and channel, estimated with an amplitude estimator (default FAE, maxiter 5, with
// rescaling, as the paper) on the fully simulated circuit, next to the exact and classical maps.
// A 3D scene (cornell, spheres, or a file) gives images by the exact path sum, Monte Carlo path
// tracing, the paper's emulator (K sampled paths + amplitude estimation) and, on request, the
// fully quantum walk circuit per pixel.
#include <cstdio>
#include <string>

#include "commands.hpp"
#include "render_job.hpp"

namespace qrm_cli {

int cmd_render(args& a) {
  a.allow(render_flags());
  const render_settings s = parse_render_settings(a);
  const qrm::scene sc = load_render_scene(s);
  qrm::io::ensure_directory(s.out);
  std::string summary;
  if (sc.dims() == 2) {
    const auto r = render_lightmap(s, sc);
    summary = "{\"scene\":\"" + sc.name() + "\",\"kind\":\"lightmap\",\"cell_channels\":" +
              std::to_string(r.cell_channels) + ",\"exact_inside_interval\":" + std::to_string(r.inside_interval) +
              ",\"rmse_vs_exact\":" + json_number(r.rmse_vs_exact) + ",\"rmse_vs_classical\":" +
              json_number(r.rmse_vs_classical) + ",\"max_relative_interference\":" + json_number(r.max_interference) +
              ",\"oracle_calls\":" + std::to_string(r.a_calls) + ",\"seconds\":" + json_number(r.seconds) +
              ",\"settings\":" + settings_json(s, sc, s.effective_steps(2)) + "}";
  } else {
    const auto r = render_images_3d(s, sc);
    summary = "{\"scene\":\"" + sc.name() + "\",\"kind\":\"images\",\"seconds\":{";
    bool first = true;
    for (const auto& [m, t] : r.seconds) {
      summary += std::string(first ? "" : ",") + "\"" + m + "\":" + json_number(t);
      first = false;
    }
    summary += "},\"rmse_vs_exact\":{";
    first = true;
    for (const auto& [m, v] : r.rmse_vs_exact) {
      summary += std::string(first ? "" : ",") + "\"" + m + "\":" + json_number(v);
      first = false;
    }
    summary += "},\"settings\":" + settings_json(s, sc, s.effective_steps(3)) + "}";
  }
  if (!s.tiled()) qrm::io::write_file_atomically(fs::path(s.out) / (sc.name() + "_summary.json"), summary + "\n");
  std::printf("%s\n", summary.c_str());
  return 0;
}

}  // namespace qrm_cli
