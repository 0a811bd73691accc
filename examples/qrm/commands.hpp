// examples/qrm/commands.hpp: the qrm tool's subcommands, one source file each. Each has a flag
// table (what it accepts, what --help prints) and a run function.
#pragma once

#include "args.hpp"

namespace qrm_cli {

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

flag_table lightmap_flags();
flag_table circuit_flags();
flag_table estimate_flags();
flag_table render_flags();
flag_table merge_flags();
flag_table figures_flags();
flag_table scaling_flags();

}  // namespace qrm_cli
