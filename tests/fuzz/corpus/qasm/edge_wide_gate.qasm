
OPENQASM 3.0;
include "stdgates.inc";
qubit[8] q;
gate big a, b, c, d, e, f, g { h a; cx a, b; cx b, c; cx c, d; cx d, e; cx e, f; ccx f, a, g; }
gate six a, b, c, d, e, f { h a; ctrl(5) @ x a, b, c, d, e, f; }
big q[0], q[1], q[2], q[3], q[4], q[5], q[6];
ctrl @ big q[7], q[0], q[1], q[2], q[3], q[4], q[5], q[6];
inv @ six q[7], q[6], q[5], q[4], q[3], q[2];
