// Writes the generated seeds of fuzz_qasm into a directory (tests/fuzz/corpus/qasm holds the
// output, regenerate with `fuzz_qasm_seeds <dir>`; the edge_*.qasm seeds there are written by hand):
//  - text seeds: our own exports of small random programs of every op kind, in the logical and
//    the decomposed form, each preceded by a newline (an even first byte selects text mode);
//  - structured seeds: an odd first byte, then bytes whose first op is of each of the five kinds.
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>

#include <qrm/circuit/qasm.hpp>
#include <qrm/support/random.hpp>

#include "support/random_programs.hpp"

namespace {
void write(const std::string& path, const std::string& bytes) {
  std::ofstream f(path, std::ios::binary);
  f << bytes;
  if (!f) {
    std::fprintf(stderr, "cannot write %s\n", path.c_str());
    std::exit(1);
  }
}
}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: fuzz_qasm_seeds <directory>\n");
    return 2;
  }
  const std::string dir = argv[1];
  qrm::rng g(20260);
  for (qrm_test::op_kind kind : qrm_test::all_op_kinds) {
    for (int i = 0; i < 2; ++i) {
      const std::size_t n = 3 + static_cast<std::size_t>(i);
      qrm::program p(n);
      for (int j = 0; j < 2; ++j) p.push(qrm_test::random_op(kind, n, g));
      const std::string name = dir + "/" + qrm_test::op_kind_name(kind) + "_" + std::to_string(i);
      // Appended, not "\n" + to_qasm(...): g++ 12 -O3 warns falsely (-Wrestrict) on a literal
      // prepended to a returned string.
      std::string logical = "\n";
      logical += qrm::to_qasm(p);
      write(name + "_logical.qasm", logical);
      qrm::qasm_options o;
      o.decomposed = true;
      o.comments = false;
      o.decomposition.keep_toffoli = i == 1;
      std::string decomposed = "\n";
      decomposed += qrm::to_qasm(p, o);
      write(name + "_decomposed.qasm", decomposed);
    }
  }
  // Structured mode reads: options (odd), width, then per op an rng seed byte and a kind byte
  // (kind = byte % 5) followed by the op's own bytes.
  const char* kinds[] = {"gate1", "unitary", "add", "mux1", "mux_unitary"};
  for (unsigned k = 0; k < 5; ++k) {
    for (unsigned i = 0; i < 2; ++i) {
      std::string bytes;
      bytes += static_cast<char>(1 + 2 * g.below(16));
      bytes += static_cast<char>(2 + i);  // width 3 or 4 (1 + byte % 6)
      bytes += static_cast<char>(g.below(256));
      bytes += static_cast<char>(k);
      for (int j = 0; j < 48; ++j) bytes += static_cast<char>(g.below(256));
      write(dir + "/structured_" + kinds[k] + "_" + std::to_string(i) + ".bin", bytes);
    }
  }
  std::printf("wrote seeds into %s\n", dir.c_str());
  return 0;
}
