// examples/qrm/commands.hpp: the qrm tool's subcommands, one source file each.
#pragma once

#include "args.hpp"

namespace qrm_cli {

struct command {
  const char* name;
  const char* summary;
  int (*run)(args&);
};

// Each returns the process exit code; usage problems throw usage_error.
int cmd_version(args&);
int cmd_lightmap(args&);
int cmd_circuit(args&);
int cmd_estimate(args&);
int cmd_render(args&);
int cmd_merge(args&);
int cmd_figures(args&);
int cmd_scaling(args&);

}  // namespace qrm_cli
