%
O1234 (hand-written test program)
; a semicolon comment line
N10 g21 g90 g17 g94 (metric, absolute, XY plane)
N20 G54 M3 S8000 T1 M6
N30 G0 Z10
N40 G0 X0 Y-5
N50 G1 Z0 F300.
N60 X20. Y0 F600
N70 Y10 (modal G01, only Y changes)
N80 G2 X30 Y20 R10 (quarter turn clockwise, centre 30 10)
N90 G03 X40 Y30 I10 J0 (quarter turn counter-clockwise, centre 40 20)
N100 G91 G1 X-5 Y5 (incremental)
N110 G90
N120 G18 G03 X40 Z5 I5 K0 (ZX plane, centre X40 Z0, a quarter turn about +Y)
N130 G17 G02 X35 Y30 Z9 I-5 J0 (helix about Z, clockwise)
/N140 G1 X36
N150 G1 X35 Y35 Z0
N160 G3 X35 Y35 I5 J0 (full circle)
N170 G0 Z10
N180 M5
N190 M30
%
