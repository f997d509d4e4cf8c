# gen.py of shared/lammps-experiment, with K atom types assigned at random (per-grain mu_roll classes)
import sys, numpy as np
N=int(sys.argv[1]); seed=int(sys.argv[2]); K=int(sys.argv[3]); L=float(sys.argv[4]) if len(sys.argv)>4 else 0.5; W=0.1; RMIN,RMAX,RHO=0.96e-3,1.18e-3,1100.0
rng=np.random.default_rng(seed); radii=np.sort(rng.uniform(RMIN,RMAX,N))[::-1]
types=rng.integers(1,K+1,N)
cell=2*RMAX; ncx=int(L/cell); ncy=int(W/cell); grid={}; pos=np.zeros((N,2))
for i,r in enumerate(radii):
    while True:
        x=rng.uniform(r,L-r); y=rng.uniform(r,W-r); ix=min(int(x/L*ncx),ncx-1); iy=min(int(y/W*ncy),ncy-1); ok=True
        for dx in (-1,0,1):
            for dy in (-1,0,1):
                for j in grid.get((ix+dx,iy+dy),()):
                    if (x-pos[j,0])**2+(y-pos[j,1])**2 < (r+radii[j])**2: ok=False; break
                if not ok: break
            if not ok: break
        if ok: pos[i]=(x,y); grid.setdefault((ix,iy),[]).append(i); break
print("experiment tray\n\n%d atoms\n%d atom types\n\n%g %g xlo xhi\n-0.001 0.101 ylo yhi\n-0.001 0.06 zlo zhi\n\nAtoms # sphere\n"%(N,K,-0.03,L+0.03))
for i in range(N): print(i+1,types[i],2*radii[i],RHO,pos[i,0],pos[i,1],radii[i])
