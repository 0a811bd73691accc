// qrm/io/svg_plot.hpp: line and scatter plots written as SVG (convergence plots, accuracy
// against time), and least-squares line fits (the slope of a log-log convergence plot).
//
// A plot has named series (points joined by lines and/or drawn as markers), linear or log10
// axes, ticks at "nice" values (1, 2 or 5 times a power of ten; whole decades on log axes, with
// unlabelled minor ticks at 2..9 times each decade when few decades are shown), a title, axis
// labels and a legend. A series may ask for its least-squares line: fitted in the axes'
// coordinates (so on log-log axes it is a power law and its slope the exponent), drawn dashed
// in the series' colour over the series' x range, and its slope printed in the legend.
// Output is deterministic: coordinates are printed with two decimals by std::to_chars (no locale).
#pragma once

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <iterator>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "atomic_file.hpp"

namespace qrm::io {

enum class axis_scale { linear, log10 };
enum class marker { none, circle, square, triangle, diamond, cross };
// legend_corner: where the legend goes; automatic picks the corner (in the order top right, top
// left, bottom left, bottom right) whose legend box covers the fewest data points.
enum class legend_corner { automatic, top_right, top_left, bottom_left, bottom_right };

// plot_series: one named data set.
struct plot_series {
  std::string name;
  std::vector<double> x, y;  // same length, finite (and positive on a log10 axis)
  std::string colour;        // "#rgb", "#rrggbb" or a CSS colour name; empty: palette colour for its index
  marker mark = marker::circle;
  bool line = true;  // join the points in the given order
  bool fit = false;  // draw the least-squares line (in axis coordinates) dashed, slope in the legend
};

// plot: everything a figure shows. Sizes are in SVG user units (pixels).
struct plot {
  std::string title, x_label, y_label;
  axis_scale x_scale = axis_scale::linear, y_scale = axis_scale::linear;
  std::vector<plot_series> series;
  int width = 640, height = 440;
  legend_corner legend = legend_corner::automatic;
};

// line_fit: y = intercept + slope x by ordinary least squares over `points` points;
// r_squared = 1 - (residual sum of squares) / (total sum of squares about the mean), defined as 1
// when every y is equal (the fit is then exact).
struct line_fit {
  double slope = 0, intercept = 0, r_squared = 0;
  std::size_t points = 0;
};

}  // namespace qrm::io

namespace qrm::detail {

// Fixed-point text with `decimals` digits, never "-0".
template <int = 0>
inline std::string fixed_text(double v, int decimals) {
  char buf[64];
  auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, decimals);
  if (r.ec != std::errc()) return v < 0 ? "-1e308" : "1e308";  // only for absurd magnitudes
  std::string s(buf, r.ptr);
  if (s[0] == '-' && s.find_first_not_of("-0.") == std::string::npos) s.erase(0, 1);
  return s;
}

template <int = 0>
inline std::string general_text(double v) {
  char buf[64];
  auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 6);
  return std::string(buf, r.ptr);
}

// Text for XML content and attribute values: & < > " ' escaped. Text must be UTF-8 without
// control characters other than tab, newline and carriage return (XML 1.0 forbids them);
// anything else is std::invalid_argument naming `what` and the byte offset.
template <int = 0>
inline std::string xml_escape(std::string_view s, const std::string& what) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    std::size_t len = 1;
    if (c < 0x80) {
      if (c < 0x20 && c != '\t' && c != '\n' && c != '\r')
        throw std::invalid_argument(what + ": control character " + std::to_string(c) + " at byte " +
                                    std::to_string(i) + " cannot appear in SVG text");
      switch (c) {
        case '&': out += "&amp;"; break;
        case '<': out += "&lt;"; break;
        case '>': out += "&gt;"; break;
        case '"': out += "&quot;"; break;
        case '\'': out += "&apos;"; break;
        default: out += static_cast<char>(c);
      }
      ++i;
      continue;
    }
    // A UTF-8 sequence: lead byte, continuation bytes, no overlong forms, no surrogates, <= U+10FFFF.
    std::uint32_t cp = 0;
    if (c >= 0xC2 && c <= 0xDF) {
      len = 2, cp = c & 0x1Fu;
    } else if (c >= 0xE0 && c <= 0xEF) {
      len = 3, cp = c & 0x0Fu;
    } else if (c >= 0xF0 && c <= 0xF4) {
      len = 4, cp = c & 0x07u;
    } else {
      len = 0;
    }
    bool ok = len != 0 && i + len <= s.size();
    for (std::size_t k = 1; ok && k < len; ++k) {
      const auto cc = static_cast<unsigned char>(s[i + k]);
      ok = (cc & 0xC0u) == 0x80u;
      cp = (cp << 6) | (cc & 0x3Fu);
    }
    if (ok) ok = !(len == 3 && cp < 0x800) && !(len == 4 && (cp < 0x10000 || cp > 0x10FFFF)) &&
                 !(cp >= 0xD800 && cp <= 0xDFFF);
    if (!ok)
      throw std::invalid_argument(what + ": invalid UTF-8 at byte " + std::to_string(i));
    out.append(s.substr(i, len));
    i += len;
  }
  return out;
}

template <int = 0>
inline std::string checked_colour(const std::string& colour, const std::string& series) {
  auto hex = [](char c) { return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f') || (c >= 'A' && c <= 'F'); };
  auto alpha = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); };
  const bool is_hex = (colour.size() == 4 || colour.size() == 7) && colour[0] == '#' &&
                      std::all_of(colour.begin() + 1, colour.end(), hex);
  const bool is_name = !colour.empty() && colour.size() <= 24 && std::all_of(colour.begin(), colour.end(), alpha);
  if (!is_hex && !is_name)
    throw std::invalid_argument("svg plot: series '" + series + "' colour '" + colour +
                                "' is not #rgb, #rrggbb or a colour name");
  return colour;
}

// The default colours, in order, for series without a colour (distinct in hue and lightness).
inline constexpr const char* plot_palette[] = {"#1f4e9c", "#c8412b", "#2a8a3e", "#7b3fa0",
                                               "#d98a00", "#4a4a4a", "#00838f", "#b0306a"};

// One axis: the shown range (in axis coordinates: log10 of the value on a log axis), ticks and
// their labels.
struct plot_axis {
  double lo = 0, hi = 1;  // axis coordinates
  struct tick {
    double at;          // axis coordinate
    std::string label;  // empty: minor tick
    std::string super;  // superscript after the label (the exponent of "10")
  };
  std::vector<tick> ticks;
};

// The shown range extends 3% beyond the outer ticks, so markers on the outer ticks (often the
// data's extremes) are not cut by the frame.
template <int = 0>
inline void pad_axis(plot_axis& a) {
  const double pad = 0.03 * (a.hi - a.lo);
  a.lo -= pad;
  a.hi += pad;
}

// make_axis(lo, hi, log, have_data): the axis for data in [lo, hi] (axis coordinates).
template <int = 0>
inline plot_axis make_axis(double lo, double hi, bool log, bool have_data) {
  plot_axis a;
  if (log) {
    if (!have_data) lo = 0, hi = 1;
    auto dlo = static_cast<long>(std::floor(lo)), dhi = static_cast<long>(std::ceil(hi));
    if (dhi == dlo) ++dhi;
    a.lo = static_cast<double>(dlo);
    a.hi = static_cast<double>(dhi);
    const long decades = dhi - dlo;
    const long every = (decades + 7) / 8;  // at most about 8 labelled decades
    for (long d = dlo; d <= dhi; ++d) {
      const bool labelled = (d - dlo) % every == 0;
      a.ticks.push_back({static_cast<double>(d), labelled ? "10" : "", labelled ? std::to_string(d) : ""});
      if (decades <= 6 && d < dhi)
        for (int m = 2; m <= 9; ++m) a.ticks.push_back({static_cast<double>(d) + std::log10(m), "", ""});
    }
    pad_axis(a);
    return a;
  }
  if (!have_data) lo = 0, hi = 1;
  if (lo == hi) {
    const double pad = lo == 0 ? 1.0 : std::fabs(lo) * 0.5;
    lo -= pad;
    hi += pad;
  }
  // Step: 1, 2 or 5 times 10^e, the smallest giving at most about 6 intervals.
  const double raw = (hi - lo) / 6.0;
  int e = static_cast<int>(std::floor(std::log10(raw)));
  double unit = std::pow(10.0, e);
  double mult = 1;
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * unit >= raw * (1 - 1e-12)) {
      mult = m;
      break;
    }
  if (mult == 10) mult = 1, ++e, unit = std::pow(10.0, e);
  const double step = mult * unit;
  const double klo = std::floor(lo / step + 1e-9), khi = std::ceil(hi / step - 1e-9);
  a.lo = klo * step;
  a.hi = khi * step;
  const int decimals = std::max(0, -e);
  for (double k = klo; k <= khi; ++k) a.ticks.push_back({k * step, fixed_text(k * step, decimals), ""});
  pad_axis(a);
  return a;
}

}  // namespace qrm::detail

namespace qrm::io {

// fit_line(x, y): ordinary least squares of y on x. std::invalid_argument for different lengths,
// fewer than 2 points, a non-finite value (named by index), or all x equal.
template <int = 0>
inline line_fit fit_line(std::span<const double> x, std::span<const double> y) {
  if (x.size() != y.size())
    throw std::invalid_argument("fit_line: " + std::to_string(x.size()) + " x values but " +
                                std::to_string(y.size()) + " y values");
  const std::size_t n = x.size();
  if (n < 2) throw std::invalid_argument("fit_line: needs at least 2 points, got " + std::to_string(n));
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(x[i]) || !std::isfinite(y[i]))
      throw std::invalid_argument("fit_line: point " + std::to_string(i) + " (" + detail::general_text(x[i]) + ", " +
                                  detail::general_text(y[i]) + ") is not finite");
    mx += x[i];
    my += y[i];
  }
  mx /= static_cast<double>(n);
  my /= static_cast<double>(n);
  // Sums about the means: no cancellation between large sums of squares.
  double sxx = 0, sxy = 0, syy = 0;
  for (std::size_t i = 0; i < n; ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
    syy += (y[i] - my) * (y[i] - my);
  }
  if (sxx == 0) throw std::invalid_argument("fit_line: all x are equal (" + detail::general_text(x[0]) + ")");
  line_fit f;
  f.points = n;
  f.slope = sxy / sxx;
  f.intercept = my - f.slope * mx;
  double ss_res = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double r = y[i] - (f.intercept + f.slope * x[i]);
    ss_res += r * r;
  }
  f.r_squared = syy == 0 ? 1.0 : 1.0 - ss_res / syy;
  return f;
}

// fit_log_log(x, y): least squares of log10(y) on log10(x), i.e. y = 10^intercept x^slope.
// std::invalid_argument as fit_line, and for any x or y that is not positive (named by index).
template <int = 0>
inline line_fit fit_log_log(std::span<const double> x, std::span<const double> y) {
  if (x.size() != y.size())
    throw std::invalid_argument("fit_log_log: " + std::to_string(x.size()) + " x values but " +
                                std::to_string(y.size()) + " y values");
  if (x.size() < 2) throw std::invalid_argument("fit_log_log: needs at least 2 points, got " + std::to_string(x.size()));
  std::vector<double> lx(x.size()), ly(y.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!(x[i] > 0 && y[i] > 0 && std::isfinite(x[i]) && std::isfinite(y[i])))
      throw std::invalid_argument("fit_log_log: point " + std::to_string(i) + " (" + detail::general_text(x[i]) +
                                  ", " + detail::general_text(y[i]) + ") is not positive and finite");
    lx[i] = std::log10(x[i]);
    ly[i] = std::log10(y[i]);
  }
  return fit_line(lx, ly);
}

// render_svg(p): the SVG document. std::invalid_argument naming the series and point for
// mismatched lengths, non-finite data, non-positive data on a log10 axis, a bad colour, a fit
// that cannot be made (fewer than 2 points, all x equal), invalid UTF-8 or control characters in
// text, or a size below 200 x 150.
template <int = 0>
std::string render_svg(const plot& p) {
  using detail::fixed_text;
  if (p.width < 200 || p.height < 150 || p.width > 100000 || p.height > 100000)
    throw std::invalid_argument("render_svg: size " + std::to_string(p.width) + "x" + std::to_string(p.height) +
                                " is outside 200x150 .. 100000x100000");
  const bool xlog = p.x_scale == axis_scale::log10, ylog = p.y_scale == axis_scale::log10;

  // Validate, and gather the data range in axis coordinates.
  double xmin = HUGE_VAL, xmax = -HUGE_VAL, ymin = HUGE_VAL, ymax = -HUGE_VAL;
  std::vector<line_fit> fits(p.series.size());
  for (std::size_t s = 0; s < p.series.size(); ++s) {
    const plot_series& ser = p.series[s];
    const std::string who = "render_svg: series '" + ser.name + "'";
    if (ser.x.size() != ser.y.size())
      throw std::invalid_argument(who + " has " + std::to_string(ser.x.size()) + " x values but " +
                                  std::to_string(ser.y.size()) + " y values");
    for (std::size_t i = 0; i < ser.x.size(); ++i) {
      for (int axis = 0; axis < 2; ++axis) {
        const double v = axis == 0 ? ser.x[i] : ser.y[i];
        const char* name = axis == 0 ? "x" : "y";
        if (!std::isfinite(v))
          throw std::invalid_argument(who + " point " + std::to_string(i) + " has " + name + " = " +
                                      detail::general_text(v) + ", which is not finite");
        if ((axis == 0 ? xlog : ylog) && !(v > 0))
          throw std::invalid_argument(who + " point " + std::to_string(i) + " has " + name + " = " +
                                      detail::general_text(v) + "; a log10 axis can only show positive values");
      }
      const double tx = xlog ? std::log10(ser.x[i]) : ser.x[i], ty = ylog ? std::log10(ser.y[i]) : ser.y[i];
      xmin = std::min(xmin, tx), xmax = std::max(xmax, tx), ymin = std::min(ymin, ty), ymax = std::max(ymax, ty);
    }
    if (!ser.colour.empty()) detail::checked_colour(ser.colour, ser.name);
    if (ser.fit) {
      std::vector<double> tx(ser.x.size()), ty(ser.y.size());
      for (std::size_t i = 0; i < tx.size(); ++i) {
        tx[i] = xlog ? std::log10(ser.x[i]) : ser.x[i];
        ty[i] = ylog ? std::log10(ser.y[i]) : ser.y[i];
      }
      try {
        fits[s] = fit_line(tx, ty);
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(who + " cannot be fitted: " + e.what());
      }
    }
  }
  const bool have_data = xmin <= xmax;
  const detail::plot_axis ax = detail::make_axis(xmin, xmax, xlog, have_data);
  const detail::plot_axis ay = detail::make_axis(ymin, ymax, ylog, have_data);

  // Layout: room on the left for the longest y tick label.
  std::size_t ylabel_chars = 1;
  for (const auto& t : ay.ticks) ylabel_chars = std::max(ylabel_chars, t.label.size() + t.super.size());
  const double left = 34.0 + 7.0 * static_cast<double>(ylabel_chars), right = 30, top = p.title.empty() ? 16 : 40,
               bottom = 52;
  const double W = p.width, H = p.height;
  const double x0 = left, x1 = W - right, y0 = top, y1 = H - bottom;
  auto px = [&](double t) { return x0 + (t - ax.lo) / (ax.hi - ax.lo) * (x1 - x0); };
  auto py = [&](double t) { return y1 - (t - ay.lo) / (ay.hi - ay.lo) * (y1 - y0); };
  auto num = [](double v) { return fixed_text(v, 2); };
  auto colour_of = [&](std::size_t s) {
    return p.series[s].colour.empty() ? std::string(detail::plot_palette[s % std::size(detail::plot_palette)])
                                      : p.series[s].colour;
  };
  auto text = [](std::string_view t, const std::string& what) { return detail::xml_escape(t, what); };

  std::string o;
  // add(parts...): appends each part (string literals and strings) to the document.
  auto add = [&o](const auto&... parts) { (o.append(std::string_view(parts)), ...); };
  const std::string w_text = std::to_string(p.width), h_text = std::to_string(p.height);
  add("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
  add("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"", w_text, "\" height=\"", h_text, "\" viewBox=\"0 0 ",
      w_text, " ", h_text, "\" font-family=\"DejaVu Sans, Helvetica, Arial, sans-serif\" font-size=\"12\">\n");
  if (!p.title.empty()) add("<title>", text(p.title, "render_svg: title"), "</title>\n");
  add("<rect x=\"0\" y=\"0\" width=\"", num(W), "\" height=\"", num(H), "\" fill=\"white\"/>\n");
  add("<defs><clipPath id=\"qrm-plot-area\"><rect x=\"", num(x0), "\" y=\"", num(y0), "\" width=\"", num(x1 - x0),
      "\" height=\"", num(y1 - y0), "\"/></clipPath></defs>\n");

  // Grid, frame, ticks and tick labels.
  auto line = [&](double ax1, double ay1, double ax2, double ay2, std::string_view attributes) {
    add("<line x1=\"", num(ax1), "\" y1=\"", num(ay1), "\" x2=\"", num(ax2), "\" y2=\"", num(ay2), "\"", attributes,
        "/>\n");
  };
  add("<g class=\"grid\" stroke-width=\"1\">\n");
  for (const auto& t : ax.ticks)
    line(px(t.at), y0, px(t.at), y1, t.label.empty() ? " stroke=\"#f3f3f3\"" : " stroke=\"#dddddd\"");
  for (const auto& t : ay.ticks)
    line(x0, py(t.at), x1, py(t.at), t.label.empty() ? " stroke=\"#f3f3f3\"" : " stroke=\"#dddddd\"");
  add("</g>\n");
  add("<rect class=\"frame\" x=\"", num(x0), "\" y=\"", num(y0), "\" width=\"", num(x1 - x0), "\" height=\"",
      num(y1 - y0), "\" fill=\"none\" stroke=\"black\"/>\n");
  add("<g class=\"ticks\" stroke=\"black\">\n");
  for (const auto& t : ax.ticks) line(px(t.at), y1, px(t.at), y1 + (t.label.empty() ? 3 : 6), "");
  for (const auto& t : ay.ticks) line(x0 - (t.label.empty() ? 3 : 6), py(t.at), x0, py(t.at), "");
  add("</g>\n<g class=\"tick-labels\">\n");
  auto tick_text = [&](const detail::plot_axis::tick& t, double x, double y, std::string_view anchor) {
    add("<text x=\"", num(x), "\" y=\"", num(y), "\" text-anchor=\"", anchor, "\">", text(t.label, "tick"));
    if (!t.super.empty()) add("<tspan dy=\"-0.6em\" font-size=\"75%\">", text(t.super, "tick"), "</tspan>");
    add("</text>\n");
  };
  for (const auto& t : ax.ticks)
    if (!t.label.empty()) tick_text(t, px(t.at), y1 + 20, "middle");
  for (const auto& t : ay.ticks)
    if (!t.label.empty()) tick_text(t, x0 - 9, py(t.at) + 4, "end");
  add("</g>\n");

  // Title and axis labels.
  if (!p.title.empty())
    add("<text class=\"title\" x=\"", num((x0 + x1) / 2),
        "\" y=\"24\" text-anchor=\"middle\" font-size=\"15\" font-weight=\"bold\">", text(p.title, "render_svg: title"),
        "</text>\n");
  if (!p.x_label.empty())
    add("<text class=\"x-label\" x=\"", num((x0 + x1) / 2), "\" y=\"", num(H - 12), "\" text-anchor=\"middle\">",
        text(p.x_label, "render_svg: x label"), "</text>\n");
  if (!p.y_label.empty())
    add("<text class=\"y-label\" x=\"16\" y=\"", num((y0 + y1) / 2),
        "\" text-anchor=\"middle\" transform=\"rotate(-90 16 ", num((y0 + y1) / 2), ")\">",
        text(p.y_label, "render_svg: y label"), "</text>\n");

  // Data: lines and fitted lines clipped to the plot area, then markers on top.
  auto put_marker = [&](marker m, double cx, double cy, const std::string& colour) {
    const double r = 3.5;
    auto pt = [&](double dx, double dy) { add(num(cx + dx * r), ",", num(cy + dy * r), " "); };
    switch (m) {
      case marker::none: return;
      case marker::circle:
        add("<circle cx=\"", num(cx), "\" cy=\"", num(cy), "\" r=\"", num(r), "\" fill=\"", colour, "\"/>\n");
        return;
      case marker::square:
        add("<rect x=\"", num(cx - r), "\" y=\"", num(cy - r), "\" width=\"", num(2 * r), "\" height=\"", num(2 * r),
            "\" fill=\"", colour, "\"/>\n");
        return;
      case marker::triangle:
        add("<polygon points=\"");
        pt(0, -1.2);
        pt(-1.1, 0.8);
        pt(1.1, 0.8);
        add("\" fill=\"", colour, "\"/>\n");
        return;
      case marker::diamond:
        add("<polygon points=\"");
        pt(0, -1.3);
        pt(1.3, 0);
        pt(0, 1.3);
        pt(-1.3, 0);
        add("\" fill=\"", colour, "\"/>\n");
        return;
      case marker::cross:
        add("<path d=\"M", num(cx - r), " ", num(cy - r), "L", num(cx + r), " ", num(cy + r), "M", num(cx - r), " ",
            num(cy + r), "L", num(cx + r), " ", num(cy - r), "\" stroke=\"", colour,
            "\" stroke-width=\"1.5\" fill=\"none\"/>\n");
        return;
    }
  };
  auto tx = [&](double v) { return px(xlog ? std::log10(v) : v); };
  auto ty = [&](double v) { return py(ylog ? std::log10(v) : v); };
  add("<g class=\"data\" clip-path=\"url(#qrm-plot-area)\" fill=\"none\" stroke-width=\"1.8\">\n");
  for (std::size_t s = 0; s < p.series.size(); ++s) {
    const plot_series& ser = p.series[s];
    const std::string colour = colour_of(s);
    if (ser.line && ser.x.size() >= 2) {
      add("<polyline stroke=\"", colour, "\" points=\"");
      for (std::size_t i = 0; i < ser.x.size(); ++i)
        add(i ? " " : "", num(tx(ser.x[i])), ",", num(ty(ser.y[i])));
      add("\"/>\n");
    }
    if (ser.fit) {
      const auto [lo, hi] = std::minmax_element(ser.x.begin(), ser.x.end());
      const double a = xlog ? std::log10(*lo) : *lo, b = xlog ? std::log10(*hi) : *hi;
      const line_fit& f = fits[s];
      add("<line class=\"fit\" x1=\"", num(px(a)), "\" y1=\"", num(py(f.intercept + f.slope * a)), "\" x2=\"",
          num(px(b)), "\" y2=\"", num(py(f.intercept + f.slope * b)), "\" stroke=\"", colour,
          "\" stroke-dasharray=\"6 4\"/>\n");
    }
  }
  add("</g>\n<g class=\"markers\">\n");
  for (std::size_t s = 0; s < p.series.size(); ++s) {
    const plot_series& ser = p.series[s];
    const std::string colour = colour_of(s);
    for (std::size_t i = 0; i < ser.x.size(); ++i) put_marker(ser.mark, tx(ser.x[i]), ty(ser.y[i]), colour);
  }
  add("</g>\n");

  // Legend: one entry per series (a line sample and/or marker, the name, the fitted slope).
  if (!p.series.empty()) {
    std::vector<std::string> labels;
    std::size_t chars = 0;
    for (std::size_t s = 0; s < p.series.size(); ++s) {
      std::string label = p.series[s].name;
      if (p.series[s].fit) label.append(" (fit slope ").append(fixed_text(fits[s].slope, 3)).append(")");
      chars = std::max(chars, label.size());
      labels.push_back(std::move(label));
    }
    const double row = 18, lw = 44 + 6.8 * static_cast<double>(chars), lh = 8 + row * static_cast<double>(labels.size());
    auto box_at = [&](legend_corner c) {
      const bool at_right = c == legend_corner::top_right || c == legend_corner::bottom_right;
      const bool at_top = c == legend_corner::top_right || c == legend_corner::top_left;
      return std::pair<double, double>{at_right ? x1 - 8 - lw : x0 + 8, at_top ? y0 + 8 : y1 - 8 - lh};
    };
    legend_corner corner = p.legend;
    if (corner == legend_corner::automatic) {
      std::size_t fewest = SIZE_MAX;
      for (legend_corner c : {legend_corner::top_right, legend_corner::top_left, legend_corner::bottom_left,
                              legend_corner::bottom_right}) {
        const auto [bx, by] = box_at(c);
        std::size_t covered = 0;
        for (const plot_series& ser : p.series)
          for (std::size_t i = 0; i < ser.x.size(); ++i) {
            const double cx = tx(ser.x[i]), cy = ty(ser.y[i]);
            covered += cx >= bx - 4 && cx <= bx + lw + 4 && cy >= by - 4 && cy <= by + lh + 4;
          }
        if (covered < fewest) fewest = covered, corner = c;
      }
    }
    const auto [lx, ly] = box_at(corner);
    add("<g class=\"legend\">\n<rect x=\"", num(lx), "\" y=\"", num(ly), "\" width=\"", num(lw), "\" height=\"",
        num(lh), "\" fill=\"white\" fill-opacity=\"0.85\" stroke=\"#999999\"/>\n");
    for (std::size_t s = 0; s < labels.size(); ++s) {
      const plot_series& ser = p.series[s];
      const std::string colour = colour_of(s);
      const double cy = ly + 4 + row * (static_cast<double>(s) + 0.5);
      if (ser.line || ser.fit) {
        const std::string stroke = " stroke=\"" + colour + "\" stroke-width=\"1.8\"";
        line(lx + 6, cy, lx + 34, cy, ser.line ? stroke : stroke + " stroke-dasharray=\"6 4\"");
      }
      put_marker(ser.mark, lx + 20, cy, colour);
      add("<text x=\"", num(lx + 40), "\" y=\"", num(cy + 4), "\">", text(labels[s], "render_svg: series name"),
          "</text>\n");
    }
    add("</g>\n");
  }
  add("</svg>\n");
  return o;
}

// write_svg(path, p): renders the plot and writes it atomically.
template <int = 0>
void write_svg(const std::filesystem::path& path, const plot& p) { write_file_atomically(path, render_svg(p)); }

}  // namespace qrm::io

// This header's part of <qrm/io/compiled_io.hpp> (QRM_COMPILED_IO).
#define QRM_DETAIL_SVG_PLOT_INSTANCES(PREFIX)                          \
  PREFIX std::string render_svg<0>(const plot&);                       \
  PREFIX void write_svg<0>(const std::filesystem::path&, const plot&);
#ifdef QRM_COMPILED_IO
namespace qrm::io {
QRM_DETAIL_SVG_PLOT_INSTANCES(extern template)
}  // namespace qrm::io
#endif
