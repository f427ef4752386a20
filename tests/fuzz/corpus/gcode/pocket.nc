%
(pocket.nc: mtcal example part, mm. An 80 x 50 mm contour with R10 corners, a helical bore,)
(a quarter arc in the YZ plane and an incremental G91 section.)
(Program zero: lower-left corner of the contour on the top face.)
(On examples/machines/vmc-3axis.yaml run it with --origin "X=-40,Y=-25,Z=-400".)
N10 G21 G17 G90 G40 G49 G80 G94
N20 T1 M6 (10 mm end mill)
N30 S8000 M3
N40 G0 X10 Y0 Z5
N50 G1 Z-2 F300
; contour, counter-clockwise: straight sides, corners alternately by I J and by R
N60 X70 F800
N70 G3 X80 Y10 I0 J10
N80 G1 Y40
N90 G3 X70 Y50 R10
N100 G1 X10
N110 G3 X0 Y40 I0 J-10
N120 G1 Y10
N130 G3 X10 Y0 R10
N140 G0 Z5
; helical bore of radius 8 at (40, 25): two turns down 2 mm each, then a full circle at the bottom
N150 G0 X48 Y25
N160 G1 Z0 F300
N170 G3 X48 Y25 Z-2 I-8 J0 F400
N180 G3 Z-4 I-8
N190 G3 I-8
N200 G1 X40 Y25
N210 G0 Z5
; a quarter arc in the YZ plane (G19) at X=20: down the side, round onto the top face
N220 G0 X20 Y5
N230 G1 Z-5 F300
N240 G19 G2 Y10 Z0 J5 K0
N250 G17
; incremental steps along the top face (G91), back to absolute
N260 G91 G1 X5 F600
N270 Y5
N280 X5 Y-5
N290 G90 G0 Z5
N300 M5
N310 M30
%
