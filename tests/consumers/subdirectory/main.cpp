// A user's program: build a tiny walk-shaped circuit and read P(out = 1).
#include <cmath>
#include <cstdio>

#include <qrm/qrm.hpp>

using pos = qrm::position<"x", 2>;
using dir = qrm::direction<1>;
using out = qrm::output<>;
using L = qrm::layout<pos, dir, out>;

int main() {
  auto c = qrm::make_circuit<L>(qrm::h<dir>{}, qrm::increment<pos, qrm::on<dir>>{},
                                qrm::x<out, qrm::when<pos, 1>>{});
  qrm::state_vector<double> s(L::width);
  qrm::run(s, c);
  const double p = qrm::probability<L, qrm::on<out>>(s);
  std::printf("P(out=1) = %.3f\n", p);
  return std::abs(p - 0.5) < 1e-12 ? 0 : 1;
}
