// qrm scaling: width and depth of the A operator over the sweeps of qrm::scaling_sweep(), least-
// squares exponents against the paper's Section 6 (width O(s + log p + log d), depth
// O(s (p^3 + d))), written as scaling.csv, scaling.md and SVG plots. Everything is counted, not
// timed (times come from bench_scaling), so the output is the same on every machine.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include <qrm/io/atomic_file.hpp>
#include <qrm/io/csv.hpp>
#include <qrm/io/progress.hpp>
#include <qrm/io/svg_plot.hpp>
#include <qrm/walk/cost.hpp>
#include "scaling_study.hpp"
#include <qrm/version.hpp>

#include "commands.hpp"

namespace qrm_cli {

namespace {

using qrm::pruning;
using qrm::walk_layer;
using qrm::walk_variant;
using key = std::tuple<unsigned, unsigned, unsigned, std::size_t, walk_variant, pruning>;

key key_of(const qrm::scaling_case& c) {
  return {c.dims, c.size, c.steps, c.directions, c.variant, c.prune};
}

// The measured points, and the series a fit or a plot reads from them.
class study {
 public:
  explicit study(std::map<key, qrm::scaling_result> r) : results_(std::move(r)) {}

  const qrm::scaling_result& at(unsigned dims, unsigned p, unsigned s, std::size_t d, walk_variant v,
                                pruning pr) const {
    const auto it = results_.find({dims, p, s, d, v, pr});
    if (it == results_.end()) throw std::logic_error("qrm scaling: a point the report needs was not measured");
    return it->second;
  }
  const std::map<key, qrm::scaling_result>& all() const { return results_; }

 private:
  std::map<key, qrm::scaling_result> results_;
};

// A series: x values and a quantity read from each point (nullopt: not measured, left out).
struct series {
  std::vector<double> x, y;
};
using quantity = std::function<std::optional<double>(const qrm::scaling_result&)>;

quantity logical_depth() {
  return
      [](const qrm::scaling_result& r) { return std::optional<double>(static_cast<double>(r.logical.logical_depth)); };
}
quantity layer_depth(walk_layer l) {
  return [l](const qrm::scaling_result& r) { return std::optional<double>(static_cast<double>(r.layers[l])); };
}
quantity decomposed_depth() {
  return [](const qrm::scaling_result& r) {
    return r.decomposed ? std::optional<double>(static_cast<double>(r.decomposed->depth)) : std::nullopt;
  };
}
quantity cnot_count() {
  return [](const qrm::scaling_result& r) {
    return r.decomposed ? std::optional<double>(static_cast<double>(r.decomposed->cnot_count)) : std::nullopt;
  };
}
quantity width() {
  return [](const qrm::scaling_result& r) { return std::optional<double>(static_cast<double>(r.width)); };
}

// The sweeps the report reads (fixed parameters as in qrm::scaling_sweep).
struct sweep {
  const char* name;  // for tables: "p (3D, s = 2, d = 15)"
  char varies;       // 'p', 's' or 'd'
  unsigned dims;
  std::vector<double> values;
  unsigned p, s;
  std::size_t d;
};
const sweep p3{"p (3D Cornell box, s = 2, d = 15)", 'p', 3, {8, 16, 32, 64}, 0, 2, 15};
const sweep p2{"p (2D box, s = 3, d = 8)", 'p', 2, {4, 8, 16, 32, 64, 128, 256}, 0, 3, 8};
const sweep s3{"s (3D Cornell box, p = 8, d = 15)", 's', 3, {1, 2, 3, 4, 5, 6, 7, 8}, 8, 0, 15};
const sweep s2{"s (2D box, p = 16, d = 8)", 's', 2, {1, 2, 3, 4, 5, 6, 7, 8}, 16, 0, 8};
const sweep d3{"d (3D Cornell box, p = 8, s = 3)", 'd', 3, {6, 14, 15, 26, 32, 64, 128}, 8, 3, 0};
const sweep d3_golden{"d (3D, golden-spiral sets only, p = 8, s = 3)", 'd', 3, {15, 32, 64, 128}, 8, 3, 0};

const qrm::scaling_result& point(const study& st, const sweep& sw, double v, walk_variant var, pruning pr) {
  const auto u = static_cast<unsigned>(v);
  return st.at(sw.dims, sw.varies == 'p' ? u : sw.p, sw.varies == 's' ? u : sw.s,
               sw.varies == 'd' ? static_cast<std::size_t>(v) : sw.d, var, pr);
}

// The sweep's points with x in [lo, hi] that have the quantity.
series collect(
    const study& st, const sweep& sw, walk_variant var, pruning pr, const quantity& q, double lo = 0, double hi = 1e300,
    const std::function<double(double)>& x_of = [](double v) { return v; }) {
  series out;
  for (double v : sw.values) {
    if (v < lo || v > hi) continue;
    const auto y = q(point(st, sw, v, var, pr));
    if (!y) continue;
    out.x.push_back(x_of(v));
    out.y.push_back(*y);
  }
  return out;
}

std::string fixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}
std::string window_text(const series& s) {
  return s.x.empty()
             ? "-"
             : fixed(s.x.front(), 0) + "..." + fixed(s.x.back(), 0) + " (" + std::to_string(s.x.size()) + " points)";
}
const char* variant_name(walk_variant v) {
  return v == walk_variant::faithful ? "faithful" : "history";
}

// The points with y > 0 (a log axis or a log-log fit cannot take the empty circuits of walks
// that reach no light).
series positive(const series& s) {
  series out;
  for (std::size_t i = 0; i < s.x.size(); ++i)
    if (s.y[i] > 0) {
      out.x.push_back(s.x[i]);
      out.y.push_back(s.y[i]);
    }
  return out;
}

// Least-squares exponent rows: log-log (power laws) or linear (slopes).
struct fit_rows {
  qrm::io::table t{{"quantity", "sweep", "pruning", "fit window", "fit", "fitted", "r^2", "expected"}};
  void add(const std::string& what, const sweep& sw, pruning pr, const series& all, bool log_log,
           const std::string& expected) {
    const series s = log_log ? positive(all) : all;
    if (s.x.size() < 2 || std::all_of(s.x.begin(), s.x.end(), [&](double x) { return x == s.x[0]; })) return;
    const qrm::io::line_fit f = log_log ? qrm::io::fit_log_log(s.x, s.y) : qrm::io::fit_line(s.x, s.y);
    t.add_row({what, sw.name, qrm::pruning_name(pr), window_text(s), log_log ? "exponent (log-log)" : "slope (linear)",
               fixed(f.slope, 3), fixed(f.r_squared, 5), expected});
  }
};

qrm::io::plot_series plot_of(const std::string& name, const series& all, bool fit, qrm::io::marker m,
                             const std::string& colour, bool log_y = true) {
  const series s = log_y ? positive(all) : all;
  qrm::io::plot_series p;
  p.name = name;
  p.x = s.x;
  p.y = s.y;
  p.fit = fit && s.x.size() >= 2;
  p.mark = m;
  p.colour = colour;
  return p;
}

std::string cell_or_dash(const std::optional<std::size_t>& v) {
  return v ? std::to_string(*v) : "-";
}

}  // namespace

flag_table scaling_flags() {
  const char* g = "scaling";
  flag_table f{
      {"out", "DIR", "", "output directory for the CSV, Markdown and SVG plots (required)", g},
      {"start", "near_light|centre", "near_light", "the walk's start cell in each scene", g},
      {"no-decompose", "", "", "skip the decomposed (1-qubit + CNOT) counts, the slow part", g},
  };
  add_progress_flags(f, g);
  return f;
}

int cmd_scaling(args& a) {
  a.allow(scaling_flags());
  const std::filesystem::path out = a.required("out");
  const std::string start_name = a.str("start", "near_light");
  qrm::scaling_start where = qrm::scaling_start::near_light;
  if (start_name == "centre")
    where = qrm::scaling_start::centre;
  else if (start_name != "near_light")
    throw usage_error("--start must be near_light or centre, got '" + start_name + "'");
  const bool decompose = !a.flag("no-decompose");
  const qrm::io::progress_options po = progress_from_flags(a);
  const bool quiet = a.flag("quiet");
  qrm::io::ensure_directory(out);  // before the measurements, so a bad --out fails at once

  // Measure every distinct point once (the sweeps share some).
  std::map<key, qrm::scaling_case> todo;
  for (qrm::scaling_case c : qrm::scaling_sweep()) {
    c.decompose = c.decompose && decompose;
    todo.emplace(key_of(c), c);
  }
  std::map<key, qrm::scaling_result> results;
  {
    qrm::io::progress bar("qrm scaling", todo.size(), po);
    for (const auto& [k, c] : todo) {
      results.emplace(k, qrm::measure_scaling_case(c, where));
      bar.advance();
    }
  }
  const study st(std::move(results));
  constexpr auto faithful = walk_variant::faithful, history = walk_variant::history;
  constexpr auto none = pruning::none, scene = pruning::scene, reachable = pruning::reachable;

  // ---- scaling.csv: every point --------------------------------------------------------------
  qrm::io::table csv({"dims",
                      "p",
                      "s",
                      "d",
                      "variant",
                      "pruning",
                      "start_x",
                      "start_y",
                      "start_z",
                      "start_direction",
                      "width",
                      "width_formula",
                      "full_width",
                      "logical_depth",
                      "depth_closed_form",
                      "gate_count",
                      "depth_init",
                      "depth_coin",
                      "depth_history",
                      "depth_shift",
                      "depth_sample",
                      "depth_path",
                      "shift_pairs",
                      "decomposed_depth",
                      "cnot_count",
                      "single_qubit_count",
                      "ancillas"});
  std::size_t unpruned = 0, width_ok = 0, depth_ok = 0, pruned = 0, pruned_ok = 0;
  for (const auto& [k, r] : st.all()) {
    const auto& c = r.where;
    const bool is_unpruned = c.prune == none;
    std::vector<qrm::io::cell> row = {c.dims,
                                      c.size,
                                      c.steps,
                                      c.directions,
                                      variant_name(c.variant),
                                      qrm::pruning_name(c.prune),
                                      r.start.voxel[0],
                                      r.start.voxel[1],
                                      r.start.voxel[2],
                                      r.start.direction,
                                      r.width,
                                      r.width_formula,
                                      r.full_width,
                                      r.logical.logical_depth};
    row.push_back(is_unpruned ? qrm::io::cell(r.unpruned_depth_formula) : qrm::io::cell(""));
    row.push_back(r.logical.gate_count);
    for (walk_layer l : qrm::all_walk_layers) row.push_back(r.layers[l]);
    row.push_back(r.shift_pairs);
    if (r.decomposed) {
      for (std::size_t v :
           {r.decomposed->depth, r.decomposed->cnot_count, r.decomposed->single_qubit_count, r.decomposed->ancillas})
        row.push_back(v);
    } else {
      for (int i = 0; i < 4; ++i) row.push_back("");
    }
    csv.add_row(std::move(row));
    if (is_unpruned) {
      ++unpruned;
      width_ok += r.width == r.width_formula ? 1 : 0;
      depth_ok += r.logical.logical_depth == r.unpruned_depth_formula ? 1 : 0;
    } else {
      ++pruned;
      const auto& full = st.at(c.dims, c.size, c.steps, c.directions, c.variant, none);
      pruned_ok += r.width <= full.width && r.logical.logical_depth <= full.logical.logical_depth &&
                           r.logical.gate_count <= full.logical.gate_count
                       ? 1
                       : 0;
    }
  }
  qrm::io::write_csv(out / "scaling.csv", csv);

  // ---- fitted exponents ----------------------------------------------------------------------
  fit_rows fits;
  const auto sample = layer_depth(walk_layer::sample), coin = layer_depth(walk_layer::coin),
             shift = layer_depth(walk_layer::shift);
  for (const sweep* sw : {&p3, &p2}) {
    const double lo = 8;  // 2D: p = 4 left out (the constant s a + init is 23% of its depth)
    const std::string power = sw->dims == 3 ? "3 (paper: p^3 voxels, one gate each per step)" : "2 (p^2 cells)";
    const std::string dims = std::to_string(sw->dims);
    const std::string bounded = "0 (the walk's reach is bounded by s, not p)";
    for (pruning pr : {none, scene, reachable})
      fits.add("Sample layer depth vs p", *sw, pr, collect(st, *sw, faithful, pr, sample, lo), true,
               pr == none ? power
               : pr == scene
                   ? "-> " + dims +
                         (sw->dims == 3 ? " (air has rho = 1: only the zero-reflectance shell goes, a shrinking share)"
                                        : " (air has rho = 1: only the green wall, red channel 0, goes)")
                   : bounded);
    for (pruning pr : {none, scene})
      fits.add("Coin layer depth vs p", *sw, pr, collect(st, *sw, faithful, pr, coin, lo), true,
               pr == none      ? power
               : sw->dims == 3 ? "-> 2 (surface voxels)"
                               : "1 (wall cells)");
    for (pruning pr : {none, scene, reachable})
      fits.add("Logical depth vs p", *sw, pr, collect(st, *sw, faithful, pr, logical_depth(), lo), true,
               pr == none    ? "-> " + dims + " (closed form: (3s - 1) p^" + dims + " + s a + ...)"
               : pr == scene ? "-> " + dims + " (the rho layer keeps every air voxel)"
                             : bounded);
    if (sw->dims == 2) {
      const std::string why =
          "~1 at these p: identity coins (air) and Ry(0) vanish when lowered; the wall cells' "
          "coins (~4p, each O(log p) CNOTs) dominate";
      fits.add("Decomposed depth (1q + CNOT) vs p", *sw, none, collect(st, *sw, faithful, none, decomposed_depth(), lo),
               true, why);
      fits.add("CNOT count vs p", *sw, none, collect(st, *sw, faithful, none, cnot_count(), lo), true, why);
      fits.add("Decomposed depth (1q + CNOT) vs p", *sw, reachable,
               collect(st, *sw, faithful, reachable, decomposed_depth(), lo), true,
               "~0 (+ log p: controls on P-qubit registers)");
    }
  }
  for (const sweep* sw : {&s3, &s2}) {
    const auto& one = point(st, *sw, 1, faithful, none);
    const double p = sw->p, cells = std::pow(p, sw->dims);
    const double per_step = 3 * cells + static_cast<double>(one.shift_pairs);
    for (pruning pr : {none, scene, reachable})
      fits.add("Logical depth vs s", *sw, pr, collect(st, *sw, faithful, pr, logical_depth(), 2), true,
               pr == reachable ? "> 1 while the reachable set grows with s (up to 1 + dims)"
                               : "1 (paper: s steps; (3s - 1) makes the fit 1.1 from s = 2)");
    fits.add("Logical depth per step", *sw, none, collect(st, *sw, faithful, none, logical_depth()), false,
             fixed(per_step, 0) + " = 3 p^" + std::to_string(sw->dims) +
                 " + a (a = " + std::to_string(one.shift_pairs) + " adds)");
    fits.add("Decomposed depth (1q + CNOT) vs s", *sw, none, collect(st, *sw, faithful, none, decomposed_depth(), 2),
             true, "1");
    fits.add("Decomposed depth (1q + CNOT) vs s", *sw, reachable,
             collect(st, *sw, faithful, reachable, decomposed_depth(), 2), true, "> 1 (the reachable set grows)");
  }
  fits.add("Shift layer depth vs d", d3, none, collect(st, d3, faithful, none, shift), true,
           "1 (paper: the + d term); cube sets (d = 6, 14, 26) have more zero displacements");
  fits.add("Shift layer depth vs d", d3_golden, none, collect(st, d3_golden, faithful, none, shift), true,
           "1 (a ~ 3 d: golden-spiral directions move on every axis)");
  for (pruning pr : {none, scene, reachable})
    fits.add("Logical depth vs d", d3, pr, collect(st, d3, faithful, pr, logical_depth()), true,
             pr == none    ? "~0 here: p^3 = 512 dominates s a (a <= 3 d)"
             : pr == scene ? "~0 (the rho layer's p^3 dominates)"
                           : "~1 (the shift layer dominates; more directions also reach more voxels)");
  fits.add("Logical depth per direction", d3, none, collect(st, d3, faithful, none, logical_depth()), false,
           "s a / d <= 3 s = 9");

  // Width: linear in log2 p, s and the direction bits.
  qrm::io::table wfits(
      {"quantity", "sweep", "variant", "fit window", "fitted slope", "r^2", "formula", "measured increments"});
  auto width_fit = [&](const std::string& what, const sweep& sw, walk_variant v,
                       const std::function<double(double)>& x_of, const std::string& formula) {
    const series s = collect(st, sw, v, none, width(), 0, 1e300, x_of);
    const qrm::io::line_fit f = qrm::io::fit_line(s.x, s.y);
    std::string inc;
    for (std::size_t i = 1; i < s.y.size(); ++i) {
      if (i > 1) inc += ' ';
      inc += fixed(s.y[i] - s.y[i - 1], 0);  // appended piecewise: g++ 12 -Wrestrict false alarm on "x" + string
    }
    wfits.add_row(
        {what, sw.name, variant_name(v), window_text(s), fixed(f.slope, 3), fixed(f.r_squared, 5), formula, inc});
  };
  auto log2_of = [](double v) { return std::log2(v); };
  auto dir_bits = [](double v) { return static_cast<double>(qrm::bits_for(static_cast<std::uint64_t>(v))); };
  auto identity = [](double v) { return v; };
  for (walk_variant v : {faithful, history}) {
    width_fit("width vs log2 p", p2, v, log2_of, "2 (2 axes of P = log2 p qubits)");
    width_fit("width vs log2 p", p3, v, log2_of, "3 (3 axes of P = log2 p qubits)");
    width_fit("width vs s", s2, v, identity,
              v == faithful ? "2 per step (Le, rho) + 1 where ceil(log2 s) grows"
                            : "2 + 3 per step + 1 where ceil(log2 s) grows");
    width_fit("width vs s", s3, v, identity,
              v == faithful ? "2 per step (Le, rho) + 1 where ceil(log2 s) grows"
                            : "2 + 4 per step (D = 4 history qubits) + 1 where ceil(log2 s) grows");
    width_fit("width vs D = ceil(log2 d)", d3, v, dir_bits,
              v == faithful ? "1 (the direction register)" : "s = 3 (direction + 2 history copies)");
  }

  // ---- where the decomposed circuit's CNOTs come from (2D, unpruned, decomposed points) --------
  qrm::io::table layer_cnots({"p", "CNOTs", "coin", "shift", "sample", "path", "init", "coin share",
                              "coin entries lowered (non-identity)", "CNOTs per lowered coin entry"});
  for (double v : p2.values) {
    const auto& r = point(st, p2, v, faithful, none);
    if (!r.decomposed) continue;
    const qrm::walk_model m = qrm::scaling_model(2, r.where.size, 8);
    qrm::walk_options o;
    o.steps = r.where.steps;
    o.prune = none;
    const qrm::walk_program w = qrm::make_walk_program(m, r.start, o);
    const auto parts = qrm::walk_layer_programs(w.circuit);
    std::array<std::size_t, 6> cx{};
    for (walk_layer l : qrm::all_walk_layers)
      cx[static_cast<std::size_t>(l)] = qrm::decomposed_metrics(parts[static_cast<std::size_t>(l)]).cnot_count;
    std::size_t lowered_entries = 0;  // coin entries whose matrix is not the identity (air's is)
    for (const qrm::op::any& x : parts[static_cast<std::size_t>(walk_layer::coin)].ops()) {
      const auto& mux = std::get<qrm::op::mux_unitary_op>(x);
      for (const auto& e : mux.entries)
        lowered_entries += mux.matrices[e.matrix] == qrm::dense_matrix::identity(mux.matrices[e.matrix].dim) ? 0 : 1;
    }
    const std::size_t coin = cx[static_cast<std::size_t>(walk_layer::coin)];
    layer_cnots.add_row(
        {static_cast<std::size_t>(v), r.decomposed->cnot_count, coin, cx[static_cast<std::size_t>(walk_layer::shift)],
         cx[static_cast<std::size_t>(walk_layer::sample)], cx[static_cast<std::size_t>(walk_layer::path)],
         cx[static_cast<std::size_t>(walk_layer::init)],
         fixed(100.0 * static_cast<double>(coin) / static_cast<double>(r.decomposed->cnot_count), 1) + "%",
         lowered_entries,
         fixed(static_cast<double>(coin) / static_cast<double>(std::max<std::size_t>(lowered_entries, 1)), 0)});
  }

  // ---- per-sweep tables (faithful variant; the history variant is in scaling.csv) ---------------
  auto sweep_table = [&](const sweep& sw) {
    qrm::io::table t({std::string(1, sw.varies), "width", "width (reachable)", "depth", "closed form", "depth (scene)",
                      "depth (reachable)", "sample layer", "coin layer", "shift layer", "decomposed depth", "CNOTs",
                      "decomposed depth (reachable)", "CNOTs (reachable)"});
    for (double v : sw.values) {
      const auto& n = point(st, sw, v, faithful, none);
      const auto& sc = point(st, sw, v, faithful, scene);
      const auto& re = point(st, sw, v, faithful, reachable);
      auto dec = [](const qrm::scaling_result& r, bool cnot) {
        return r.decomposed ? std::optional<std::size_t>(cnot ? r.decomposed->cnot_count : r.decomposed->depth)
                            : std::nullopt;
      };
      t.add_row({static_cast<std::size_t>(v), n.width, re.width, n.logical.logical_depth, n.unpruned_depth_formula,
                 sc.logical.logical_depth, re.logical.logical_depth, n.layers[walk_layer::sample],
                 n.layers[walk_layer::coin], n.layers[walk_layer::shift], cell_or_dash(dec(n, false)),
                 cell_or_dash(dec(n, true)), cell_or_dash(dec(re, false)), cell_or_dash(dec(re, true))});
    }
    return qrm::io::to_markdown(t);
  };

  // ---- plots ---------------------------------------------------------------------------------
  using qrm::io::marker;
  auto depth_vs_p = [&](const sweep& sw, const std::string& file) {
    qrm::io::plot pl;
    pl.title = std::string("Depth of A vs positions per axis p (") +
               (sw.dims == 3 ? "3D, s = 2, d = 15)" : "2D, s = 3, d = 8)");
    pl.x_label = "positions per axis p";
    pl.y_label = "depth";
    pl.x_scale = pl.y_scale = qrm::io::axis_scale::log10;
    const double lo = 8;
    pl.series.push_back(plot_of("logical, unpruned", collect(st, sw, faithful, none, logical_depth(), lo), true,
                                marker::circle, "#1f4e9c"));
    pl.series.push_back(
        plot_of("sample layer, unpruned", collect(st, sw, faithful, none, sample, lo), true, marker::cross, "#7b3fa0"));
    pl.series.push_back(plot_of("logical, scene-pruned", collect(st, sw, faithful, scene, logical_depth(), lo), true,
                                marker::square, "#2a8a3e"));
    pl.series.push_back(plot_of("logical, reachable-pruned", collect(st, sw, faithful, reachable, logical_depth(), lo),
                                true, marker::triangle, "#c8412b"));
    pl.legend = qrm::io::legend_corner::top_left;
    qrm::io::write_svg(out / file, pl);
  };
  depth_vs_p(p3, "depth_vs_p_3d.svg");
  depth_vs_p(p2, "depth_vs_p_2d.svg");
  {
    qrm::io::plot pl;
    pl.title = "Logical vs decomposed (1q + CNOT) depth (2D, s = 3, d = 8)";
    pl.x_label = "positions per axis p";
    pl.y_label = "depth or gates";
    pl.x_scale = pl.y_scale = qrm::io::axis_scale::log10;
    pl.series.push_back(plot_of("1q+CNOT, unpruned", collect(st, p2, faithful, none, decomposed_depth(), 8), true,
                                marker::diamond, "#e08a00"));
    pl.series.push_back(
        plot_of("CNOTs, unpruned", collect(st, p2, faithful, none, cnot_count(), 8), true, marker::cross, "#7b3fa0"));
    pl.series.push_back(plot_of("logical, unpruned", collect(st, p2, faithful, none, logical_depth(), 8, 64), true,
                                marker::circle, "#1f4e9c"));
    pl.series.push_back(plot_of("1q+CNOT, reachable", collect(st, p2, faithful, reachable, decomposed_depth(), 8), true,
                                marker::triangle, "#c8412b"));
    pl.width = 720;  // room for the legend right of the smallest p
    pl.legend = qrm::io::legend_corner::bottom_right;
    qrm::io::write_svg(out / "decomposed_vs_p_2d.svg", pl);
  }
  {
    qrm::io::plot pl;
    pl.title = "Depth of A vs steps s (2D p = 16; 3D p = 8, d = 15)";
    pl.x_label = "steps s";
    pl.y_label = "logical depth";
    pl.x_scale = pl.y_scale = qrm::io::axis_scale::log10;
    pl.series.push_back(
        plot_of("3D unpruned", collect(st, s3, faithful, none, logical_depth(), 2), true, marker::circle, "#1f4e9c"));
    pl.series.push_back(plot_of("3D reachable-pruned", collect(st, s3, faithful, reachable, logical_depth(), 2), true,
                                marker::triangle, "#c8412b"));
    pl.series.push_back(
        plot_of("2D unpruned", collect(st, s2, faithful, none, logical_depth(), 2), true, marker::square, "#2a8a3e"));
    pl.series.push_back(plot_of("2D reachable-pruned", collect(st, s2, faithful, reachable, logical_depth(), 2), true,
                                marker::diamond, "#e08a00"));
    pl.legend = qrm::io::legend_corner::bottom_right;
    qrm::io::write_svg(out / "depth_vs_s.svg", pl);
  }
  {
    qrm::io::plot pl;
    pl.title = "Depth of A vs directions d (3D, p = 8, s = 3)";
    pl.x_label = "directions d";
    pl.y_label = "depth";
    pl.x_scale = pl.y_scale = qrm::io::axis_scale::log10;
    pl.series.push_back(plot_of("logical, unpruned", collect(st, d3, faithful, none, logical_depth()), true,
                                marker::circle, "#1f4e9c"));
    pl.series.push_back(
        plot_of("shift layer, unpruned", collect(st, d3, faithful, none, shift), true, marker::cross, "#7b3fa0"));
    pl.series.push_back(plot_of("logical, reachable-pruned", collect(st, d3, faithful, reachable, logical_depth()),
                                true, marker::triangle, "#c8412b"));
    pl.legend = qrm::io::legend_corner::bottom_right;
    qrm::io::write_svg(out / "depth_vs_d.svg", pl);
  }
  {
    qrm::io::plot pl;
    pl.title = "Width of A vs steps s (unpruned)";
    pl.x_label = "steps s";
    pl.y_label = "qubits";
    pl.series.push_back(plot_of("3D history (p = 8, d = 15)", collect(st, s3, history, none, width()), true,
                                marker::circle, "#1f4e9c", false));
    pl.series.push_back(plot_of("3D faithful (p = 8, d = 15)", collect(st, s3, faithful, none, width()), true,
                                marker::square, "#2a8a3e", false));
    pl.series.push_back(plot_of("2D history (p = 16)", collect(st, s2, history, none, width()), true, marker::triangle,
                                "#c8412b", false));
    pl.series.push_back(plot_of("2D faithful (p = 16)", collect(st, s2, faithful, none, width()), true, marker::diamond,
                                "#e08a00", false));
    pl.legend = qrm::io::legend_corner::top_left;
    qrm::io::write_svg(out / "width_vs_s.svg", pl);
  }

  // ---- scaling.md ----------------------------------------------------------------------------
  std::string md;
  md += "# Width and depth of the A operator against the paper's Section 6\n\n";
  md += "Written by `qrm scaling --out DIR";
  if (where == qrm::scaling_start::centre) md += " --start centre";
  if (!decompose) md += " --no-decompose";
  md += "` (qrm " + std::string(qrm::version) +
        "). Every number here is counted, not timed: the same on every machine. Times: bench_scaling.\n\n";
  md +=
      "- Circuits: `make_walk_program(model, start, {s, variant, pruning})` (include/qrm/walk/circuit.hpp). 2D: `box_2d(p)` "
      "with the paper's 8 directions; 3D: `cornell_box(p)` with `sphere_directions(d, 3)` (3 fractional position "
      "bits).\n";
  md +=
      where == qrm::scaling_start::near_light
          ? "- Start (light-map start): two cells below the light, 2D (p/2 - 1, 2), 3D (p/2, p - 4, p/2), so light is "
            "reachable in 2 steps at every p (from the centre, the light is more than s steps away at most points "
            "with p >= 16, where the reachable-pruned circuit is empty; `--start centre`).\n"
          : "- Start (light-map start): the centre, 2D (p/2 - 2, p/2 - 2), 3D (p/2, p/2, p/2). At most points with "
            "p >= 16 the light is more than s steps away: the reachable-pruned circuit is then empty, and points "
            "with a zero depth are left out of the log-log fits and plots.\n";
  md +=
      "- Logical depth: `qrm::circuit_metrics_of` (ASAP layers; a multiplexed gate is one layer per entry, i.e. one gate per "
      "voxel, as the paper counts; a multi-controlled gate is one layer). Layer depths: each layer's ops on their own "
      "(`qrm::walk_layers`). Decomposed: `qrm::decompose` to single-qubit gates and CNOTs with clean ancillas, where "
      "it takes a few seconds (see `qrm::scaling_sweep`); `-` elsewhere.\n";
  md +=
      "- Pruning: `none` = the paper's circuit (every voxel gets a coin and sample entry); `scene` = no coin for air, "
      "no sample gate for zero values, no term that cannot fire; `reachable` = also only the voxels the walk can "
      "occupy at each step.\n\n";
  md += "## Fitted exponents (faithful variant; the history variant adds exactly s - 1 layers)\n\n";
  md += "Least squares of log(y) on log(x) (exponent) or of y on x (slope), over the window shown.\n\n";
  md += qrm::io::to_markdown(fits.t) + "\n";
  md += "## Width\n\n";
  md +=
      "width = 1 (out) + ceil(log2 s) [at least 1] (steps) + s (Le) + (s - 1) (rho) [+ (s - 1) D (history)] + D "
      "(direction, D = ceil(log2 d)) + dims (log2 p + F) (position; F = 0 in 2D, 3 in 3D).\n\n";
  md +=
      "One more step adds 2 qubits (Le_s and rho_{s-1}), plus 1 where the steps register grows (s = 3, 5, 9, ...), "
      "plus D in the history variant: the paper's O(s + log p + log d) with these constants. The unpruned width "
      "equals the formula at " +
      std::to_string(width_ok) + " of " + std::to_string(unpruned) +
      " unpruned points; pruning only removes qubits (pruned width, depth and gate count <= unpruned at " +
      std::to_string(pruned_ok) + " of " + std::to_string(pruned) + " pruned points).\n\n";
  md += qrm::io::to_markdown(wfits) + "\n";
  md += "## Depth of the unpruned circuit, closed form\n\n";
  md +=
      "depth = init + (3 s - 1) p^dims + s a + [history] (s - 1) + 1, with a = the (direction, axis) pairs with a "
      "nonzero displacement (one controlled add each; a <= dims d), init = 1 (basis start or H on the directions) or "
      "the depth of the uniform preparation over d directions (d not a power of two). Derivation: "
      "include/qrm/walk/cost.hpp. Measured = closed form at " +
      std::to_string(depth_ok) + " of " + std::to_string(unpruned) +
      " unpruned points. So depth is O(s (p^dims + d)): the paper's O(s (p^3 + d)) in 3D.\n\n";
  md += "## Where the decomposed circuit's CNOTs come from (2D box, s = 3, unpruned)\n\n";
  md +=
      "Each layer lowered on its own (`qrm::decompose` of the layer's ops). Air's identity coins and the "
      "Ry(0) of zero values lower to nothing, so the coins of the ~4p wall cells dominate, each costing more CNOTs "
      "as p grows (its 2 log2 p select qubits are controls).\n\n";
  md += qrm::io::to_markdown(layer_cnots) + "\n";
  for (const sweep* sw : {&p3, &p2, &s3, &s2, &d3})
    md += "## Sweep over " + std::string(sw->name) + "\n\n" + sweep_table(*sw) + "\n";
  md += "## Figures\n\n";
  for (const char* f : {"depth_vs_p_3d.svg", "depth_vs_p_2d.svg", "decomposed_vs_p_2d.svg", "depth_vs_s.svg",
                        "depth_vs_d.svg", "width_vs_s.svg"})
    md += "![" + std::string(f) + "](" + f + ")\n\n";
  qrm::io::write_file_atomically(out / "scaling.md", md);
  if (!quiet)
    std::fprintf(stderr, "qrm scaling: %zu points; wrote %s/{scaling.csv, scaling.md, 6 SVG plots}\n", st.all().size(),
                 out.string().c_str());
  return width_ok == unpruned && depth_ok == unpruned && pruned_ok == pruned ? 0 : 1;
}

}  // namespace qrm_cli
