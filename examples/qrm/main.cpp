// examples/qrm/main.cpp: the qrm command-line tool (`qrm <command> [--flag value]...`).
#include <algorithm>
#include <cstdio>
#include <exception>
#include <new>
#include <string>
#include <vector>

#include <qrm/io/atomic_file.hpp>
#include <qrm/version.hpp>

#include "commands.hpp"

namespace qrm_cli {

flag_table no_flags() { return {}; }

int cmd_version(args& a) {
  a.allow(no_flags());
  std::printf("qrm %s\n", qrm::version);
  return 0;
}

const command commands[] = {
    {"render", "render a scene: 2D light maps (amplitude estimation on the simulated circuit) or 3D images",
     "qrm render --scene cornell --width 256 --height 256 --method exact,mc --out out", render_flags, cmd_render},
    {"figures", "the paper's figures (light map, 3D images, convergence, cost) into one directory",
     "qrm figures --out figures", figures_flags, cmd_figures},
    {"lightmap", "exact light maps of a 2D scene: faithful, history and classical, as CSV or JSON",
     "qrm lightmap --scene paper_8x8 --exact --backend dense --format csv", lightmap_flags, cmd_lightmap},
    {"circuit", "width, depth and gate counts of one start cell's A operator at every pruning level; QASM export",
     "qrm circuit --scene paper_8x8 --x 3 --y 4 --qasm a.qasm", circuit_flags, cmd_circuit},
    {"estimate", "estimate a Bernoulli amplitude with fae, iqae, mlae, canonical, qcoin, mc or chebae",
     "qrm estimate --probability 0.2 --estimator iqae --epsilon 0.001 --format text", estimate_flags, cmd_estimate},
    {"merge", "put the tiles of a render (qrm render --tile I/N) back together", "qrm merge --parts out",
     merge_flags, cmd_merge},
    {"scaling", "width and depth of A over s, p and d, fitted against the paper's O(s(p^3 + d))",
     "qrm scaling --out scaling", scaling_flags, cmd_scaling},
    {"resources", "what one cell's amplitude estimate would cost on a fault-tolerant quantum computer",
     "qrm resources --scene paper_8x8 --x 3 --y 4 --preset ion --format text", resources_flags, cmd_resources},
    {"noise", "one cell's walk on a noisy quantum computer: the damped Grover oscillation and the estimators' bias",
     "qrm noise --scene paper_4x4 --x 1 --y 1 --rates 1e-5,1e-4 --out noise", noise_flags, cmd_noise},
    {"crossover", "at what error fault-tolerant amplitude estimation would beat Monte Carlo on this CPU",
     "qrm crossover --scene paper_8x8 --x 3 --y 4 --out crossover", crossover_flags, cmd_crossover},
    {"simulate", "run a circuit (OpenQASM 3 or a random suite) on the dense backend, fused or not, and time it",
     "qrm simulate --random 24 --gates 300 --scalar complex-float --threads 1 --compare", simulate_flags,
     cmd_simulate},
    {"version", "print the version", "qrm version", no_flags, cmd_version},
};

void print_usage(std::FILE* out) {
  std::fprintf(out,
               "qrm %s: quantum ray marching (Mosier, McGuire, Hachisuka, SIGGRAPH Asia 2023)\n\n"
               "usage: qrm <command> [--flag value]...\n"
               "       qrm <command> --help     the command's flags, defaults and an example\n"
               "       qrm --version\n\ncommands:\n",
               qrm::version);
  for (const auto& c : commands) std::fprintf(out, "  %-10s %s\n", c.name, c.summary);
}

// One flag's line: "  --name VALUE" padded, the meaning, and the default.
void print_flag(std::FILE* out, const flag& f) {
  std::string left = std::string("  --") + f.name + (*f.value ? std::string(" ") + f.value : std::string());
  std::string right = f.meaning;
  if (*f.fallback) right += std::string(" (default: ") + f.fallback + ")";
  if (left.size() > 30) {
    std::fprintf(out, "%s\n%-32s%s\n", left.c_str(), "", right.c_str());
  } else {
    std::fprintf(out, "%-32s%s\n", left.c_str(), right.c_str());
  }
}

void print_command_help(std::FILE* out, const command& c) {
  std::fprintf(out, "usage: qrm %s [--flag value]...\n%s\n", c.name, c.summary);
  const flag_table flags = c.flags();
  std::vector<std::string> groups;
  for (const flag& f : flags)
    if (std::find(groups.begin(), groups.end(), f.group) == groups.end()) groups.push_back(f.group);
  for (const std::string& g : groups) {
    std::fprintf(out, "\n%s:\n", g.c_str());
    for (const flag& f : flags)
      if (g == f.group) print_flag(out, f);
  }
  std::fprintf(out, "\n  --help, -h                    print this and exit\n\nexample:\n  %s\n", c.example);
}

const command* find_command(const std::string& name) {
  for (const auto& c : commands)
    if (name == c.name) return &c;
  return nullptr;
}

int unknown_command(const std::string& name) {
  std::fprintf(stderr, "qrm: unknown command '%s'\n\n", name.c_str());
  print_usage(stderr);
  return 2;
}

}  // namespace qrm_cli

int main(int argc, char** argv) {
  using namespace qrm_cli;
  // SIGINT, SIGTERM, SIGHUP: remove the temporary files of writes in flight, exit 130, 143, 129.
  qrm::io::remove_temporary_files_on_signals();
  if (argc < 2) {
    print_usage(stderr);
    return 2;
  }
  const std::string name = argv[1];
  if (name == "--help" || name == "-h" || (name == "help" && argc == 2)) {
    print_usage(stdout);
    return 0;
  }
  if (name == "--version" || name == "-V") {
    std::printf("qrm %s\n", qrm::version);
    return 0;
  }
  if (name == "help") {  // qrm help CMD
    const command* c = find_command(argv[2]);
    if (!c) return unknown_command(argv[2]);
    if (argc > 3) {
      std::fprintf(stderr, "qrm help: takes one command name, got %d\n", argc - 2);
      return 2;
    }
    print_command_help(stdout, *c);
    return 0;
  }
  const command* c = find_command(name);
  if (!c) return unknown_command(name);
  const std::vector<std::string> rest(argv + 2, argv + argc);
  for (const std::string& a : rest)
    if (a == "--help" || a == "-h") {
      print_command_help(stdout, *c);
      return 0;
    }
  try {
    args a(name, rest);
    return c->run(a);
  } catch (const usage_error& e) {
    std::fprintf(stderr, "qrm %s: %s\n", name.c_str(), e.what());
    return 2;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "qrm %s: out of memory (try fewer voxels, steps, pixels or a stronger --prune)\n",
                 name.c_str());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "qrm %s: error: %s\n", name.c_str(), e.what());
    return 1;
  }
}
