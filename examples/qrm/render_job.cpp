// examples/qrm/render_job.cpp: the render jobs of render_job.hpp, compiled once for the commands
// that share them (render, figures, merge, crossover, resources) instead of in each.
#include "render_job.hpp"

namespace qrm_cli {

qrm::render::tile parse_tile(const std::string& v) {
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

qrm::noise_model parse_noise_flag(const std::string& v) {
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

unsigned default_voxels(const std::string& scene) {
  return scene == "cornell_mirror" || scene == "cornell_glossy" ? 32 : 8;
}

render_settings parse_render_settings(args& a) {
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

bool wants(const render_settings& s, const std::string& method) {
  std::stringstream ss(s.methods);
  for (std::string m; std::getline(ss, m, ',');)
    if (m == method || (m == "all" && method != "quantum")) return true;
  return false;
}

bool render_settings::quantum_run() const { return wants(*this, "quantum"); }

bool builtin_3d_scene(const std::string& name) {
  return name == "cornell" || name == "spheres" || name == "cornell_mirror" || name == "cornell_glossy" ||
         name == "cornell_fog";
}

qrm::scene load_render_scene(const render_settings& s) {
  if (s.scene == "cornell") return qrm::render::cornell_box(s.voxels);
  if (s.scene == "spheres") return qrm::render::two_spheres(s.voxels);
  if (s.scene == "cornell_mirror") return qrm::render::cornell_mirror(s.voxels);
  if (s.scene == "cornell_glossy") return qrm::render::cornell_glossy(s.voxels, 2.0);
  if (s.scene == "cornell_fog") return qrm::render::cornell_fog(s.voxels);
  return scene_from_arg(s.scene, "paper_4x4, paper_8x8, cornell, spheres, cornell_mirror, cornell_glossy, cornell_fog");
}

void check_render_flags_apply(const args& a, const render_settings& s, const qrm::scene& sc) {
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

std::string tile_suffix(const render_settings& s) {
  return s.tiled() ? ".part-" + std::to_string(s.part.index) + "-of-" + std::to_string(s.part.count) : std::string();
}

void write_image(const render_settings& s, const std::string& base, const qrm::io::image& img,
                        std::vector<std::string>& written, std::size_t block) {
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

void write_manifest(const render_settings& s, const std::string& kind, const std::vector<std::string>& bases,
                           const json_object& settings) {
  json_object j;
  j.add("kind", kind).add("tile", s.part.index).add("tiles", s.part.count).add("settings", settings);
  j.add("images", json_array::of(bases));
  qrm::io::write_file_atomically(fs::path(s.out) / ("manifest" + tile_suffix(s) + ".json"), j.str() + "\n");
}

json_object settings_json(const render_settings& s, const qrm::scene& sc, unsigned steps) {
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

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void write_lightmap_figures(const render_settings& s, const std::string& base,
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

lightmap_summary render_lightmap(const render_settings& s, const qrm::scene& sc) {
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

qrm::render::camera scene_camera(const render_settings& s, const qrm::scene& sc) {
  if (const auto& v = sc.view())
    return qrm::render::camera(v->position, v->look_at, v->up, v->vertical_fov_degrees, s.width, s.height);
  if (sc.size() < 8)
    throw usage_error("--scene " + s.scene + " is " + std::to_string(sc.size()) +
                      "^3 voxels and has no camera block; the default (Cornell box) camera needs at least 8^3. "
                      "Add a line 'camera position X Y Z look_at X Y Z' (README: scene files)");
  return qrm::render::box_scene_camera(sc.size(), s.width, s.height);
}

void add_walk_target_flags(flag_table& f, const char* group) {
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

walk_target walk_target_from_flags(const args& a) {
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

studied_walk study_walk(const qrm::scene& sc, std::optional<qrm::march_mode> march, unsigned x, unsigned y,
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

image3d_summary render_images_3d(const render_settings& s, const qrm::scene& sc) {
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
