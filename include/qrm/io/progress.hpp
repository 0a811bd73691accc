// qrm/io/progress.hpp: a progress bar on stderr for long work (rendering pixels, light-map cells).
//
// Any number of threads call advance(); the count is an atomic, and at most one thread redraws,
// at most once per redraw interval (100 ms: 10 redraws a second), under a mutex so lines never
// mix. Where the output goes decides the style (progress_style::automatic):
//   - a terminal (isatty): one line "label [#####-----]  45.2%  123/456  elapsed 12.3s  ETA 15.0s"
//     redrawn in place with "\r"; finish() draws the final state and ends the line with "\n";
//   - not a terminal (a log file, ctest): plain lines, at most one per plain interval (10 s), so a
//     short job prints nothing at all; if any line was printed, finish() prints a final
//     "label: done ..." line;
//   - quiet = true (or progress_style::off): nothing.
// A job predicted (after 2 s of work) to take more than 3 minutes says so once, in both styles:
// "label: this will take about 1h02m in all (predicted from 3 of 192 done in 2.1s)".
// To print other text while a bar is shown, use message(): it clears the bar, prints the line
// and redraws the bar, so the two never interleave.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <mutex>
#include <stdexcept>
#include <string>
#include <string_view>

#if defined(__unix__) || defined(__APPLE__)
#include <unistd.h>
#endif

namespace qrm::io {

enum class progress_style {
  automatic,  // terminal if the output is a terminal, plain otherwise
  terminal,   // redrawn in place
  plain,      // occasional whole lines
  off,        // nothing
};

// progress_options: where and how a progress bar draws.
struct progress_options {
  bool quiet = false;  // true: draw nothing (same as style = off)
  progress_style style = progress_style::automatic;
  std::FILE* out = stderr;
  std::chrono::milliseconds redraw_interval{100};   // terminal style
  std::chrono::milliseconds plain_interval{10000};  // plain style
  // Once `calibration` has passed and some work is done, a job whose predicted total time
  // exceeds `warn_longer_than` says so in one line (any style but off), so that the user can
  // stop it early rather than find out from the ETA. 0 = never.
  std::chrono::milliseconds warn_longer_than{180000};
  std::chrono::milliseconds calibration{2000};
};

}  // namespace qrm::io

namespace qrm::detail {

// "12.3s", "2m05s", "1h02m".
template <int = 0>
inline std::string duration_text(double seconds) {
  char buf[32];
  if (!(seconds >= 0) || seconds > 1e9) return "--";
  if (seconds < 60) {
    std::snprintf(buf, sizeof buf, "%.1fs", seconds);
  } else if (seconds < 3600) {
    const auto s = static_cast<long>(seconds);
    std::snprintf(buf, sizeof buf, "%ldm%02lds", s / 60, s % 60);
  } else {
    const auto m = static_cast<long>(seconds / 60);
    std::snprintf(buf, sizeof buf, "%ldh%02ldm", m / 60, m % 60);
  }
  return buf;
}

template <int = 0>
inline bool is_terminal(std::FILE* f) {
#if defined(__unix__) || defined(__APPLE__)
  return f != nullptr && ::isatty(::fileno(f)) == 1;
#else
  (void)f;
  return false;  // no portable test: behave as if writing to a log
#endif
}

}  // namespace qrm::detail

namespace qrm::io {

// progress: counts `total` units of work done by any number of threads; see the header comment.
class progress {
 public:
  // progress(label, total, options): starts the clock. total = 0 is allowed (shown as complete).
  template <int = 0>
  progress(std::string label, std::uint64_t total, progress_options options = {})
      : label_(std::move(label)), total_(total), options_(options), start_(clock::now()) {
    if (options_.out == nullptr) options_.quiet = true;
    style_ = options_.quiet ? progress_style::off : options_.style;
    if (style_ == progress_style::automatic)
      style_ = detail::is_terminal(options_.out) ? progress_style::terminal : progress_style::plain;
    if (options_.redraw_interval.count() < 0 || options_.plain_interval.count() < 0)
      throw std::invalid_argument("progress: negative redraw interval");
    const auto interval = style_ == progress_style::terminal ? options_.redraw_interval : options_.plain_interval;
    interval_ns_ = std::chrono::duration_cast<std::chrono::nanoseconds>(interval).count();
    // The first terminal draw comes at once; the first plain line only after a whole interval.
    next_draw_ns_.store(style_ == progress_style::terminal ? 0 : interval_ns_);
  }
  progress(const progress&) = delete;
  progress& operator=(const progress&) = delete;
  ~progress() {
    try {
      finish();
    } catch (...) {  // a destructor must not throw; a failed final draw is not worth a crash
    }
  }

  // advance(n): n more units done; safe from any thread; redraws when the interval has passed.
  template <int = 0>
  void advance(std::uint64_t n = 1) {
    const std::uint64_t done = done_.fetch_add(n, std::memory_order_relaxed) + n;
    if (style_ == progress_style::off || finished_.load(std::memory_order_relaxed)) return;
    const std::int64_t now = elapsed_ns();
    if (!predicted_.load(std::memory_order_relaxed)) predict(now, done);
    std::int64_t next = next_draw_ns_.load(std::memory_order_relaxed);
    // Only the thread that moves the deadline forward draws; the others go straight back to work.
    if (now < next || !next_draw_ns_.compare_exchange_strong(next, now + interval_ns_)) return;
    std::lock_guard<std::mutex> lock(mutex_);
    if (!finished_.load()) draw(false);
  }

  // done(): units counted so far.
  std::uint64_t done() const { return done_.load(); }
  // redraws(): how many times the bar or a plain line has been drawn (for tests).
  template <int = 0>
  std::uint64_t redraws() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return redraws_;
  }

  // message(line): prints `line` and a newline without garbling the bar (always printed, even
  // when quiet: it is the caller's own output).
  template <int = 0>
  void message(std::string_view line) {
    std::lock_guard<std::mutex> lock(mutex_);
    print_line(line);
  }

  // finish(): draws the final state and ends the line (terminal style); later calls do nothing.
  template <int = 0>
  void finish() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (finished_.exchange(true)) return;
    if (style_ == progress_style::terminal || (style_ == progress_style::plain && redraws_ > 0)) draw(true);
  }

 private:
  using clock = std::chrono::steady_clock;

  template <int = 0>
  std::int64_t elapsed_ns() const {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(clock::now() - start_).count();
  }

  // The one-time prediction of the total time (see progress_options::warn_longer_than).
  template <int = 0>
  void predict(std::int64_t now, std::uint64_t done) {
    const auto warn = std::chrono::duration_cast<std::chrono::nanoseconds>(options_.warn_longer_than).count();
    const auto calibration = std::chrono::duration_cast<std::chrono::nanoseconds>(options_.calibration).count();
    if (warn <= 0 || now < calibration || done == 0 || total_ == 0 || predicted_.exchange(true)) return;
    const double total_s = static_cast<double>(now) * 1e-9 * static_cast<double>(total_) / static_cast<double>(done);
    if (total_s * 1e9 <= static_cast<double>(warn)) return;
    char buf[200];
    std::snprintf(buf, sizeof buf, "%s: this will take about %s in all (predicted from %llu of %llu done in %s)",
                  label_.c_str(), detail::duration_text(total_s).c_str(), static_cast<unsigned long long>(done),
                  static_cast<unsigned long long>(total_), detail::duration_text(static_cast<double>(now) * 1e-9).c_str());
    std::lock_guard<std::mutex> lock(mutex_);
    if (!finished_.load()) print_line(buf);
  }

  // Called with mutex_ held.
  template <int = 0>
  void print_line(std::string_view line) {
    std::FILE* out = options_.out != nullptr ? options_.out : stderr;
    if (style_ == progress_style::terminal && shown_chars_ > 0 && !finished_.load()) {
      std::fprintf(out, "\r%*s\r%.*s\n", static_cast<int>(shown_chars_), "", static_cast<int>(line.size()),
                   line.data());
      shown_chars_ = 0;
      draw(false);
    } else {
      std::fprintf(out, "%.*s\n", static_cast<int>(line.size()), line.data());
      std::fflush(out);
    }
  }

  // Called with mutex_ held.
  template <int = 0>
  void draw(bool final) {
    const std::uint64_t done = done_.load();
    const double fraction = total_ == 0 ? 1.0 : static_cast<double>(done) / static_cast<double>(total_);
    const double elapsed = static_cast<double>(elapsed_ns()) * 1e-9;
    std::string line = label_;
    char buf[160];
    if (style_ == progress_style::terminal) {
      constexpr int bar = 30;
      const double shown = fraction < 0 ? 0 : fraction > 1 ? 1 : fraction;
      const int filled = static_cast<int>(shown * bar);
      line += " [" + std::string(static_cast<std::size_t>(filled), '#') +
              std::string(static_cast<std::size_t>(bar - filled), '-') + "]";
    } else {
      line += final ? ": done" : ":";
    }
    std::snprintf(buf, sizeof buf, " %5.1f%%  %llu/%llu  elapsed %s", 100.0 * fraction,
                  static_cast<unsigned long long>(done), static_cast<unsigned long long>(total_),
                  detail::duration_text(elapsed).c_str());
    line += buf;
    if (!final) {
      const double eta = done == 0 ? -1 : elapsed * (static_cast<double>(total_) - static_cast<double>(done)) /
                                               static_cast<double>(done);
      line += "  ETA " + (eta < 0 && done < total_ ? std::string("--") : detail::duration_text(eta < 0 ? 0 : eta));
    }
    std::FILE* out = options_.out;
    if (style_ == progress_style::terminal) {
      // Pad with spaces over the previous, possibly longer, line; no terminal escape codes.
      const std::size_t pad = shown_chars_ > line.size() ? shown_chars_ - line.size() : 0;
      std::fprintf(out, "\r%s%*s%s", line.c_str(), static_cast<int>(pad), "", final ? "\n" : "");
      shown_chars_ = final ? 0 : line.size();
    } else {
      std::fprintf(out, "%s\n", line.c_str());
    }
    std::fflush(out);
    ++redraws_;
  }

  std::string label_;
  std::uint64_t total_;
  progress_options options_;
  progress_style style_ = progress_style::off;
  clock::time_point start_;
  std::int64_t interval_ns_ = 0;
  std::atomic<std::uint64_t> done_{0};
  std::atomic<std::int64_t> next_draw_ns_{0};
  std::atomic<bool> finished_{false};
  std::atomic<bool> predicted_{false};  // the total-time prediction has been made
  mutable std::mutex mutex_;
  std::size_t shown_chars_ = 0;  // length of the bar currently on the terminal line
  std::uint64_t redraws_ = 0;
};

}  // namespace qrm::io
