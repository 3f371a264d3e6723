# The inputs of README's point cloud and wireframe pictures, from CGAL's meshes: bunny_points.ply
# (the bunny's vertices, with normals and a colour by height, binary PLY) and elephant_wire.obj (the
# elephant's edges as OBJ l lines, with a blue material). Run: python3 points_lines_inputs.py DIR
import math, struct
def read_off(p):
    t = open(p).read().split()
    assert t[0] == 'OFF'
    nv, nf = int(t[1]), int(t[2]); i = 4
    v = [tuple(map(float, t[i+3*k:i+3*k+3])) for k in range(nv)]; i += 3*nv
    f = []
    for _ in range(nf):
        n = int(t[i]); f.append(tuple(map(int, t[i+1:i+1+n]))); i += 1+n
    return v, f
import sys
D = sys.argv[1] + '/'  # the folder of CGAL's bunny00.off and elephant.off (libcgal-demo's data.tar.gz)
v, f = read_off(D+'bunny00.off')
n = [[0.0,0.0,0.0] for _ in v]
for a,b,c in f:
    A,B,C = v[a],v[b],v[c]
    u=[B[k]-A[k] for k in range(3)]; w=[C[k]-A[k] for k in range(3)]
    cr=[u[1]*w[2]-u[2]*w[1], u[2]*w[0]-u[0]*w[2], u[0]*w[1]-u[1]*w[0]]
    for x in (a,b,c):
        for k in range(3): n[x][k]+=cr[k]
ys=[p[1] for p in v]; lo,hi=min(ys),max(ys)
with open('bunny_points.ply','wb') as o:
    o.write(('ply\nformat binary_little_endian 1.0\ncomment the CGAL bunny\'s vertices\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n'%len(v)).encode())
    for p,nn in zip(v,n):
        t=(p[1]-lo)/(hi-lo)
        r,g,b=int(40+200*t), int(120+100*(1-abs(2*t-1))), int(230-190*t)
        o.write(struct.pack('<6f3B',*p,*nn,r,g,b))
v, f = read_off(D+'elephant.off')
edges=set()
for face in f:
    for k in range(len(face)):
        a,b=face[k],face[(k+1)%len(face)]
        edges.add((min(a,b),max(a,b)))
open('elephant_wire.mtl','w').write('newmtl wire\nKd 0.08 0.22 0.5\n')
with open('elephant_wire.obj','w') as o:
    o.write('# the CGAL elephant\'s edges as OBJ l lines\nmtllib elephant_wire.mtl\nusemtl wire\n')
    for p in v: o.write('v %g %g %g\n'%p)
    for a,b in sorted(edges): o.write('l %d %d\n'%(a+1,b+1))
print(len(v), len(edges))
