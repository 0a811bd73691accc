// examples/qrm/commands.hpp: the qrm tool's subcommands, one source file each. Each has a flag
// table (what it accepts, what --help prints) and a run function.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include <qrm/io/progress.hpp>
#include <qrm/walk/scene.hpp>

#include "args.hpp"

namespace qrm_cli {

// --quiet and --progress, for every command that shows progress on stderr.
inline void add_progress_flags(flag_table& f, const char* group) {
  f.push_back({"quiet", "", "", "no progress on stderr", group});
  f.push_back({"progress", "", "", "progress lines even when stderr is not a terminal (a log: one line every 10 s)", group});
}

// Progress as the flags ask: a bar redrawn in place on a terminal; nothing in a log unless
// --progress; nothing at all with --quiet.
inline qrm::io::progress_options progress_from_flags(args& a) {
  const bool quiet = a.flag("quiet"), always = a.flag("progress");
  if (quiet && always) throw usage_error("give either --quiet or --progress, not both");
  qrm::io::progress_options o;
  const bool terminal = qrm::detail::is_terminal(o.out);
  o.quiet = quiet || (!terminal && !always);
  o.style = terminal ? qrm::io::progress_style::terminal : qrm::io::progress_style::plain;
  return o;
}

struct command {
  const char* name;
  const char* summary;
  const char* example;
  flag_table (*flags)();
  int (*run)(args&);  // the process exit code; usage problems throw usage_error
};

int cmd_version(args&);
int cmd_lightmap(args&);
int cmd_circuit(args&);
int cmd_estimate(args&);
int cmd_render(args&);
int cmd_merge(args&);
int cmd_figures(args&);
int cmd_scaling(args&);
int cmd_resources(args&);
int cmd_crossover(args&);
int cmd_simulate(args&);
int cmd_noise(args&);

// The crossover study (cmd_crossover.cpp; qrm figures runs it too): writes crossover.csv,
// crossover.md and crossover.svg into `out`.
struct crossover_request {
  qrm::scene scene;
  std::string scene_arg = "paper_8x8";  // as the user named it (for the report)
  // 2D: the light-map cell (x, y); 3D: pixel (x, y) of a width x height image through the
  // scene's camera, walked from its first hit as qrm render --method quantum does.
  unsigned x = 3, y = 4, steps = 3;
  unsigned width = 32, height = 32;
  // The walk's march: this, else the scene's, else the surface march in 3D (with the 14 cube
  // directions, as qrm render --method quantum) and the paper's voxel march in 2D.
  std::optional<qrm::march_mode> march;
  double error_budget = 1e-3;
  std::size_t repetitions = 64;
  std::uint64_t seed = 1;
  unsigned threads = 0;
  std::string out = "crossover";
  qrm::io::progress_options progress;
};
struct crossover_result {
  std::string summary_json, markdown;
};
crossover_result run_crossover(const crossover_request& r);

flag_table lightmap_flags();
flag_table circuit_flags();
flag_table noise_flags();
flag_table estimate_flags();
flag_table render_flags();
flag_table merge_flags();
flag_table figures_flags();
flag_table scaling_flags();
flag_table resources_flags();
flag_table crossover_flags();
flag_table simulate_flags();

}  // namespace qrm_cli
