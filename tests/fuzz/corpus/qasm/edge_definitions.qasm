
OPENQASM 3.0;
include "stdgates.inc";
qubit[4] q;
gate bell(theta) a, b { ry(theta) a; cx a, b; }
gate twice(t) a, b { bell(t) a, b; bell(-t / 2) b, a; gphase(t); }
gate rot(a1, a2, a3) x { U(a1, a2, a3) x; rz(a1 * a2 - a3 ** 2) x; }
gate empty a { }
twice(pi / 4) q[0], q[1];
ctrl @ twice(1.5) q[2], q[0], q[3];
inv @ bell(0.3) q[3], q[2];
negctrl @ rot(0.1, 0.2, 0.3) q[1], q[0];
empty q[2];
ctrl @ empty q[0], q[1];
