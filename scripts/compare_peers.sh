#!/bin/bash
# SPDX-License-Identifier: Apache-2.0
# Side-by-side comparison of `morphmill deviation` with the peers a user would pick instead
# (CloudCompare C2M, MeshLab Hausdorff Distance, Open3D RaycastingScene), on the UV-sphere pair
# of ../shared/peers: D (r = 1.01, 998k triangles) against C (r = 1, 199k triangles).
#   1. vertices of D to C (499k points), signed where the tool can;
#   2. N area-uniform face samples of D to C (default N = 100000: MeshLab aborts on 1M).
# Agreement: each tool's min/max/mean/RMS next to the exact values of ref_dist.py (numpy, float64),
# and morphmill's per-vertex values against the exact per-vertex distances.
# Time: wall time of the whole process (loading included), best of REPEAT interleaved runs.
#
# Usage: scripts/compare_peers.sh [path/to/morphmill] [work dir]
#   env: REPEAT (default 3), N (default 100000)
# Needs (not part of CI): apt-get install -y --no-install-recommends cloudcompare meshlab xvfb xauth
#   time python3-numpy python3-scipy python3-open3d
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
mm=$(readlink -f "${1:-$here/../build/apps/morphmill}")
work=${2:-/tmp/morphmill-peers}
peers=$(readlink -f "${PEERS:-$here/../../shared/peers}")
repeat=${REPEAT:-3}
n=${N:-100000}
py=/usr/bin/python3
D=sphD_1M_r101.ply
C=sphC_200k_r100.ply

mkdir -p "$work"
cd "$work"
[ -f $D ] && [ -f $C ] || $py "$peers/make_meshes.py" > /dev/null
log=compare.log
: > $log
times=times.tsv
: > $times

# run NAME CASE COMMAND...: appends the wall time to times.tsv and the output to compare.log.
run() {
  local name=$1 case=$2
  shift 2
  echo "### $name ($case): $*" >> $log
  local start end
  start=$(date +%s.%N)
  "$@" >> $log 2>&1 || echo "FAILED: $name $case" | tee -a $log >&2
  end=$(date +%s.%N)
  echo -e "$name\t$case\t$(echo "$end - $start" | bc)" >> $times
}

echo "exact reference (ref_dist.py) ..." >&2
$py "$peers/ref_dist.py" $D $C --samples $n > ref.txt
cat ref.txt >> $log

for rep in $(seq "$repeat"); do
  echo "round $rep/$repeat ..." >&2
  run morphmill vertices "$mm" deviation $D $C --one-sided --signed --samples 0 --json mm_vertices.json
  run CloudCompare vertices bash "$peers/run_cc.sh" $D $C cc_vertices.asc
  run Open3D vertices $py "$peers/o3d_dist.py" $D $C --signed
  run MeshLab vertices bash "$peers/run_ml.sh" $D $C vert ml_vertices
  run morphmill faces "$mm" deviation $D $C --one-sided --signed --no-vertices --samples $n --json mm_faces.json
  run CloudCompare faces env SAMPLE=$n bash "$peers/run_cc.sh" $D $C cc_faces.asc
  run Open3D faces $py "$peers/o3d_dist.py" $D $C --signed --samples $n
  run MeshLab faces bash "$peers/run_ml.sh" $D $C face:$n ml_faces
done

# Per-vertex agreement of morphmill with the exact distances (a separate, untimed run).
"$mm" deviation $D $C --one-sided --signed --samples 0 --heatmap mm_heatmap.ply > /dev/null
$py - "$peers" $D $C mm_heatmap.ply <<'PY' >> $log
import sys, numpy as np
sys.path.insert(0, sys.argv[1])
import ref_dist
VP, FP = ref_dist.read_ply(sys.argv[2]); VQ, FQ = ref_dist.read_ply(sys.argv[3])
exact, sign = ref_dist.dist_to_mesh(VP, VQ, FQ)
# The heatmap PLY: binary little-endian, vertex properties x y z, a 'deviation' scalar, colours.
raw = open(sys.argv[4], 'rb').read(); end = raw.index(b'end_header\n') + 11
header = raw[:end].decode().splitlines()
types = {'float': 'f4', 'float32': 'f4', 'double': 'f8', 'float64': 'f8', 'uchar': 'u1', 'uint8': 'u1',
         'int': 'i4', 'int32': 'i4', 'uint': 'u4', 'uint32': 'u4', 'char': 'i1', 'short': 'i2', 'ushort': 'u2'}
fields, nv, in_vertex = [], 0, False
for line in header:
    w = line.split()
    if w[:2] == ['element', 'vertex']: nv, in_vertex = int(w[2]), True
    elif w[0] == 'element': in_vertex = False
    elif w[0] == 'property' and in_vertex: fields.append((w[2], '<' + types[w[1]]))
vertices = np.frombuffer(raw[end:end + nv * np.dtype(fields).itemsize], dtype=fields)
ours = vertices['deviation'].astype(np.float64)
print('morphmill per-vertex vs exact (signed): n=%d max |difference| = %.3e, max relative = %.3e' % (
    len(ours), np.abs(ours - exact * sign).max(), (np.abs(ours - exact * sign) / exact).max()))
PY

$py - $times <<'PY' | tee -a $log
import sys, collections
best = collections.defaultdict(lambda: float('inf'))
for line in open(sys.argv[1]):
    name, case, t = line.split('\t')
    best[(name, case)] = min(best[(name, case)], float(t))
for case in ('vertices', 'faces'):
    ours = best[('morphmill', case)]
    print('%s: wall time with loading, best of the rounds' % case)
    for name in ('morphmill', 'CloudCompare', 'Open3D', 'MeshLab'):
        t = best[(name, case)]
        print('  %-13s %7.2f s   %6.2fx morphmill' % (name, t, t / ours))
PY
echo "details: $work/$log" >&2
