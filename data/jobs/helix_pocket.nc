(helix_pocket.nc: a 30 x 20 mm pocket, 4 mm deep, entered by a helix)
(tool: 6 mm ball end, tool point = tip)
G21 G90 G17
T1 M6
S12000 M3
G0 Z5
G0 X40 Y30
G1 Z1 F300
(helical entry: three turns of radius 4 about X36 Y30 descending to Z-4 relative to the top at 0)
G3 X40 Y30 I-4 J0 Z-0.667 F400
G3 X40 Y30 I-4 J0 Z-2.333
G3 X40 Y30 I-4 J0 Z-4
(clean-up passes)
G1 X25 Y30 F800
G1 X25 Y22
G1 X55 Y22
G1 X55 Y38
G1 X25 Y38
G1 X25 Y30
G1 X55 Y30
(round the corners with arcs)
G2 X58 Y27 R3
G1 Z5
M5
M30
