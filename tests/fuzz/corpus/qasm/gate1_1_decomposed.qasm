
OPENQASM 3.0;
include "stdgates.inc";
qubit[4] q;
qubit[1] anc;
y q[0];
x q[1];
x q[3];
x q[2];
ccx q[1], q[3], anc[0];
ccx anc[0], q[2], q[0];
ccx q[1], q[3], anc[0];
x q[2];
x q[3];
x q[1];
