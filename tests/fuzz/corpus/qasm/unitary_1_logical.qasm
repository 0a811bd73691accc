
OPENQASM 3.0;
include "stdgates.inc";
// Written by qrm 0.1.0: 4 qubits, 2 ops, logical form: one line per gate, multiplexed gates one line per entry.
qubit[4] q;
negctrl(2) @ U(0.72065520763975366, 0, 0) q[1], q[0], q[3];
negctrl(2) @ gphase(3.1415926535897931) q[1], q[0];
ctrl @ U(0.99932996146844344, -2.7315968711194669, 2.1056270371143979) q[0], q[3];
ctrl @ gphase(2.9781153693730791) q[0];
