# Writes a CAD-like test mesh of long thin triangles: 3000 randomly oriented open tubes
# (length 8, radius 0.15) whose sides are single strips running the whole length, 48 per
# tube (288,000 triangles of aspect ~400:1), as binary PLY. Deterministic for a seed.
# Usage: python3 bench/accel/tubes_mesh.py OUT.ply [SEED]
import math, random, struct, sys
random.seed(int(sys.argv[2]) if len(sys.argv) > 2 else 1)
tubes, segments, length, radius = 3000, 48, 8.0, 0.15
verts, faces = [], []
def unit():
    while True:
        v = [random.gauss(0, 1) for _ in range(3)]
        n = math.sqrt(sum(c * c for c in v))
        if n > 1e-3: return [c / n for c in v]
def cross(a, b): return [a[1]*b[2]-a[2]*b[1], a[2]*b[0]-a[0]*b[2], a[0]*b[1]-a[1]*b[0]]
for _ in range(tubes):
    c = [random.uniform(-12, 12) for _ in range(3)]
    w = unit(); t = unit(); u = cross(w, t); n = math.sqrt(sum(x*x for x in u)); u = [x/n for x in u]; v = cross(w, u)
    base = len(verts)
    for end in (-0.5, 0.5):
        for s in range(segments):
            a = 2 * math.pi * s / segments
            verts.append([c[k] + end * length * w[k] + radius * (math.cos(a) * u[k] + math.sin(a) * v[k]) for k in range(3)])
    for s in range(segments):
        a0, a1 = base + s, base + (s + 1) % segments
        b0, b1 = a0 + segments, a1 + segments
        faces.append((a0, a1, b1)); faces.append((a0, b1, b0))
with open(sys.argv[1], 'wb') as f:
    f.write(b"ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\nelement face %d\nproperty list uchar int vertex_indices\nend_header\n" % (len(verts), len(faces)))
    for p in verts: f.write(struct.pack('<3f', *p))
    for a, b, c in faces: f.write(struct.pack('<B3i', 3, a, b, c))
print(len(faces), "triangles")
