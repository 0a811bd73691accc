
OPENQASM 3.0;
include "stdgates.inc";
// Written by qrm 0.1.0: 4 qubits, 2 ops, logical form: one line per gate, multiplexed gates one line per entry.
qubit[4] q;
negctrl @ rz(-3.224077361855715) q[3], q[2];
ctrl @ negctrl(2) @ h q[2], q[3], q[0], q[1];
ctrl(2) @ negctrl @ y q[3], q[2], q[0], q[1];
