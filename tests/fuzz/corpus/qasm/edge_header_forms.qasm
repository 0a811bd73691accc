
OPENQASM 3;
include "stdgates.inc";
qubit[1] a;
qubit b;
qreg c[3];
h a[0]; h b; h c[2]; ctrl @ x b, c[1];
