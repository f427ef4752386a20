%
O2001 (DRILL PLATE: ISO 6983-1 dialect, the way a Fanuc-style post writes it)
(work offset G54 and tool lengths from the machine's setup: mtcal toolpath --work-offset, --tool-table)
N10 G21 G17 G40 G49 G80 G90 G94
N20 G28 G91 Z0 (Z home first, by way of no intermediate point)
N30 G90 G54
N40 T1 M6 (centre drill)
N50 S2500 M3 M8
N60 G43 H1 G0 Z20.
N70 G0 X10. Y10.
N80 G98 G81 X10. Y10. Z-2. R2. F150.
N90 X60.
N100 X110.
N110 G99 Y60.
N120 X60.
N130 G98 X10.
N140 G80 M9
N150 G28 G91 Z0 M5
N160 G90 T2 M6 (8.5 mm drill)
N170 S1800 M3 M8
N180 G43 H2 G0 Z20.
N190 G98 G83 X10. Y10. Z-15. R2. Q4. F200.
N200 X110.
N210 Y60.
N220 X10.
N230 G80 M9
N240 (tapping M10: four holes, incremental, L repeats along X)
N250 G28 G91 Z0 M5
N260 G90 T3 M6
N270 S400 M3
N280 G43 H3 G0 Z20.
N290 G0 X10. Y35.
N300 G91 G98 G84 X25. Z-14. R-16. L4 F600.
N310 G90 G80
N320 G28 G91 Z0 M5
N330 G28 X0 Y0
N340 G90 M30
%
