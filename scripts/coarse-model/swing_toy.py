#!/usr/bin/env python3
"""A one-dimensional toy of the swing field (issue 40, not the automaton): N grains on a
periodic 0.1 m tray at the stripe scene's packing (0.46) move together each half period,
out and back, each by the swing the DEM measured at its local packing (the table of
docs/results/coarse-model/report.md after the onset, `aligned.py`), plus a 0.8 mm spread (the
measured spread about the neighbours' mean move). No excluded volume, no collisions, no
second dimension. `flat` gives every grain the mean swing instead (the control); `before`
uses the curve measured before the onset (what the parameter file's classes hold).

    python3 scripts/coarse-model/swing_toy.py SEED [flat|before]

Prints, every 5 s, the contrast and spread of the 1 mm area-fraction profile, the spacing of
its structure factor's peak, and the runs of at least 4 mm above 1.5 x the mean.
"""
import numpy as np, sys
rng=np.random.default_rng(int(sys.argv[1]) if len(sys.argv)>1 else 1)
L,W,N=0.1,0.02,2000; r=np.sqrt(0.46*L*W/(N*np.pi)); d=2*r; reach=2.5*0.75e-3
pk=np.array([0.15,0.25,0.35,0.45,0.55,0.65,0.75,0.85]); sw=np.array([11.90,11.62,10.78,9.54,8.90,8.96,8.40,7.90])*1e-3
flat = len(sys.argv)>2 and sys.argv[2]=='flat'
if len(sys.argv)>2 and sys.argv[2]=='before':
    # the curve measured before the onset (the parameter file's by_packing classes)
    sw=np.array([12.51,12.96,13.23,13.35,13.12,11.98,11.29,11.06])*1e-3
x=rng.uniform(0,L,N)
def phi(x):
    xs=np.sort(x); cnt=np.searchsorted(xs, x+reach)-np.searchsorted(xs, x-reach)
    # periodic wrap
    cnt+= (np.searchsorted(xs, x+reach-L)) + (N-np.searchsorted(xs, x-reach+L))
    return cnt*np.pi*r*r/(2*reach*W)
def profile(x, cells=100):
    h,_=np.histogram(x%L,bins=cells,range=(0,L)); return h*np.pi*r*r/((L/cells)*W)
for half in range(1,181):
    p=phi(x%L)
    s=np.full(N, sw.mean()) if flat else np.interp(p,pk,sw)
    x=x+(1 if half%2 else -1)*s+rng.normal(0,0.8e-3,N)
    if half%30==0:
        prof=profile(x); m=prof.mean(); c=prof.max()/m
        f=np.abs(np.fft.rfft(prof-m))**2; k=np.argmax(f[1:])+1
        thr=1.5*m; above=prof>thr
        # runs of >= 4 cells (4 mm) above threshold (periodic approx)
        runs=0; n=0
        for a in np.concatenate([above,above[:1]]):
            if a: n+=1
            else:
                if n>=4: runs+=1
                n=0
        print(f"t={half/6:.1f}s contrast(max/mean)={c:.2f} cv={prof.std()/m:.2f} S(k) peak at spacing {L/k*1e3:.1f} mm, bands(>1.5 mean, >=4mm)={runs}")
