
OPENQASM 3.0;
include "stdgates.inc";
qubit[2] q;
ry(0/0) q[0];
