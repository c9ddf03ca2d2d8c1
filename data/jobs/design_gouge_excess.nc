(design_gouge_excess.nc: the slot of design_gouge_excess_intended.json with two mistakes)
(mm, absolute; tool 1 is the job's 3 mm radius ball-end, programmed points are the tool tip)
G21 G90 G17
G0 Z25
G0 X-5 Y12
G1 Z15 F300
G1 X30 F600
G1 Z14.2 F100 (mistake 1: a plunge 0.8 mm below the slot floor at X30 - a gouge)
G1 Z15
G1 X49.7 F600 (mistake 2: stops 0.3 mm short of X50 - the end wall is left thick)
G0 Z25
M30
