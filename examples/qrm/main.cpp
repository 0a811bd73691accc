// examples/qrm/main.cpp: the qrm command-line tool (`qrm <command> [--flag value]...`).
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include <qrm/version.hpp>

#include "commands.hpp"

namespace qrm_cli {

int cmd_version(args& a) {
  a.allow({});
  std::printf("qrm %s\n", qrm::version);
  return 0;
}

static const command commands[] = {
    {"version", "print the version", cmd_version},
    {"lightmap", "exact light maps of a 2D scene: faithful, history and classical", cmd_lightmap},
    {"circuit", "metrics of one start point's A operator at every pruning level; --qasm FILE exports it", cmd_circuit},
    {"figures", "the paper's figures (light map, 3D images, convergence, cost) into --out (default figures)", cmd_figures},
    {"render", "render a scene: 2D light maps (FAE on the simulated circuit) or 3D images (exact, mc, emulated, quantum)", cmd_render},
    {"merge", "merge the tiles of a render (--parts DIR)", cmd_merge},
    {"estimate", "estimate a Bernoulli amplitude with fae, iqae, mlae, canonical, qcoin or mc", cmd_estimate},
    {"scaling", "width and depth of A over s, p and d, fitted against the paper's O(s(p^3+d)); --out DIR", cmd_scaling},
};

static void print_usage(std::FILE* out) {
  std::fprintf(out, "usage: qrm <command> [--flag value]...\ncommands:\n");
  for (const auto& c : commands) std::fprintf(out, "  %-10s %s\n", c.name, c.summary);
}

}  // namespace qrm_cli

int main(int argc, char** argv) {
  using namespace qrm_cli;
  if (argc < 2) {
    print_usage(stderr);
    return 2;
  }
  const std::string name = argv[1];
  if (name == "--help" || name == "help") {
    print_usage(stdout);
    return 0;
  }
  for (const auto& c : commands) {
    if (name != c.name) continue;
    try {
      args a(name, std::vector<std::string>(argv + 2, argv + argc));
      return c.run(a);
    } catch (const usage_error& e) {
      std::fprintf(stderr, "qrm %s: %s\n", name.c_str(), e.what());
      return 2;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "qrm %s: error: %s\n", name.c_str(), e.what());
      return 1;
    }
  }
  std::fprintf(stderr, "qrm: unknown command '%s'\n", name.c_str());
  print_usage(stderr);
  return 2;
}
