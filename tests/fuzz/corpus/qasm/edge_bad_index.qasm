
OPENQASM 3.0;
include "stdgates.inc";
qubit[2] q;
h q[0/0];
ctrl(1/0) @ x q[0], q[1];
