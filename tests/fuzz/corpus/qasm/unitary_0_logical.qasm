
OPENQASM 3.0;
include "stdgates.inc";
// Written by qrm 0.1.0: 3 qubits, 2 ops, logical form: one line per gate, multiplexed gates one line per entry.
qubit[3] q;
gate qrm_unitary2_0 a0, a1 {
  ctrl @ U(1.9155645362134799, 0, -0) a1, a0;
  ctrl @ U(1.1724218530979986, 0, -0) a0, a1;
  negctrl @ x a1, a0;
  negctrl @ U(1.7732800181002266, 3.1415926535897931, -3.1415926535897931) a0, a1;
  ctrl @ U(0.48740406086989191, 3.1415926535897931, -3.1415926535897931) a0, a1;
  negctrl @ x a1, a0;
  negctrl @ U(0.37079503805261038, 0, -0) a0, a1;
  negctrl @ U(2.3618696301801632, -3.1415926535897931, -3.1415926535897931) a1, a0;
  negctrl @ gphase(3.1415926535897931) a1;
}
qrm_unitary2_0 q[0], q[2];
negctrl @ U(0.74384987183813733, -0.21670620214248215, -4.1009178775316748) q[0], q[1];
negctrl @ gphase(2.3876782415274449) q[0];
