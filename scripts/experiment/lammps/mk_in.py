# writes in.T: K types with mu_roll uniform over [m-s, m+s]; pairs use the mean of the two
import sys
XL=float(sys.argv[6]) if len(sys.argv)>6 else 0.5; NF=int(sys.argv[7]) if len(sys.argv)>7 else 96000
m=float(sys.argv[1]); s=float(sys.argv[2]); K=int(sys.argv[3]); t2=float(sys.argv[4]); tag=sys.argv[5]
mus=[m-s+2*s*(k+0.5)/K for k in range(K)] if K>1 else [m]
E,e,nu,mu="1.0e6","5.0e7","0.3","0.4"
law=lambda mr: f"hertz/material {E} {e} {nu} damping viscoelastic tangential mindlin NULL 1.0 {mu} rolling sds 10.0 1.0e-3 {mr:.4f}"
L=[]
L+=["units si","atom_style sphere","atom_modify map array","boundary f f f","newton off","comm_modify vel yes",f"read_data data.{tag}",
    "pair_style granular"]
for i in range(K):
    for j in range(i,K):
        L.append(f"pair_coeff {i+1} {j+1} {law(0.5*(mus[i]+mus[j]))}")
for k in range(K): L.append(f"group g{k+1} type {k+1}")
L+=["timestep 2.0833333e-5","fix grav all gravity 9.81 vector 0 0 -1","fix integ all nve/sphere","neighbor 0.5e-3 bin","neigh_modify delay 0 every 1 check yes",
    "compute ncont all contact/atom","compute nc all reduce sum c_ncont","variable ppc equal c_nc/2",
    "thermo_style custom step time atoms v_ppc ke cpu","thermo_modify lost warn norm no flush yes","thermo 16000"]
def walls(A,f):
    out=[]
    for k in range(K):
        w=law(mus[k])
        out+=[f"fix fl{k} g{k+1} wall/gran granular {w} zplane 0.0 NULL wiggle x {A} {1/f}",
              f"fix sd{k} g{k+1} wall/gran granular {w} yplane 0.0 0.1 wiggle x {A} {1/f}",
              f"fix en{k} g{k+1} wall/gran granular {w} xplane 0.0 {XL} wiggle x {A} {1/f}"]
    return out
def unwalls():
    return [f"unfix {p}{k}" for k in range(K) for p in ("fl","sd","en")]
L+=walls(0.02,5.0)+[f"run {NF}"]+unwalls()+walls(0.01,3.0)
L+=["reset_timestep 0",f"dump d all custom 8000 dump.{tag}.lammpstrj id radius x y z vx vy","dump_modify d format float %.6g sort id",
    f"run {int(round(t2*48000))}"]
open(f"in.{tag}","w").write("\n".join(L)+"\n")
print(mus)
