
OPENQASM 3.0;
include "stdgates.inc";
qubit[4] q;
cx q[1], q[0];
x q[1];
