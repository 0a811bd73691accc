
OPENQASM 3.0;
include "stdgates.inc";
qubit q;
qreg r[2];
ry(sin(pi / 6) + cos(0) - tan(0.1) * arcsin(0.5) / arccos(0.2)) q;
rz(arctan(2) ** 2 - exp(-1) + ln(2) * sqrt(2)) r[0];
p(-(-(1.5e-3)) + .5 + 5. + 2E1 - tau / euler) r[1];
U(π, τ / 4, ℇ) q;
barrier q, r[0];
/* a block
   comment */ x r[1]; // trailing comment
cx r[1 + 0 * 5], q;
