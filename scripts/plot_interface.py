#!/usr/bin/python3
"""The picture of an interface in the README (docs/interface.png): two outputs of `seam pair`
(OFF) and its curves, near the curves, in 3D.

Usage: scripts/plot_interface.py A2.off B2.off CURVES.txt OUT.png
(needs python3-numpy and python3-matplotlib). docs/interface.png shows a generated crossover,
seam::make_crossover(60, 16, 48, 14, lenticular, 0.3), paired with the default options.
"""
import sys
import numpy as np, matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt
from mpl_toolkits.mplot3d.art3d import Poly3DCollection
def read_off(p):
    t=open(p).read().split('\n'); i=1
    while t[i].strip()=='' or t[i].startswith('#'): i+=1
    nv,nf=map(int,t[i].split()[:2]); i+=1
    V=np.array([list(map(float,t[i+k].split()[:3])) for k in range(nv)]); i+=nv
    F=np.array([list(map(int,t[i+k].split()[1:4])) for k in range(nf)])
    return V,F
curves=[]
for line in open(sys.argv[3]):
    a=line.split()
    if not a: continue
    n=int(a[0]); curves.append(np.array(list(map(float,a[1:1+3*n]))).reshape(n,3))
A,FA=read_off(sys.argv[1]); B,FB=read_off(sys.argv[2])
c=np.vstack(curves); lo=c.min(0)-0.35; hi=c.max(0)+0.35
def near(V,F,top=False):
    cen=V[F].mean(1); m=np.all((cen>lo)&(cen<hi),axis=1)
    if top:
        n=np.cross(V[F[:,1]]-V[F[:,0]],V[F[:,2]]-V[F[:,0]]); m&=n[:,2]>0
    return V[F[m]]
fig=plt.figure(figsize=(12,5.2))
for k,(title,which) in enumerate([('weft (blue) and warp (orange) after seam pair',(1,1)),('the weft alone, from above: the curve (red) runs along its edges',(1,0))]):
    ax=fig.add_subplot(1,2,k+1,projection='3d',computed_zorder=False)
    if which[0]: ax.add_collection3d(Poly3DCollection(near(A,FA,top=(k==1)),facecolor=(0.55,0.7,0.95,0.9 if not which[1] else 0.55),edgecolor=(0.1,0.2,0.4,0.6),linewidths=0.3))
    if which[1]: ax.add_collection3d(Poly3DCollection(near(B,FB),facecolor=(0.98,0.7,0.4,0.55),edgecolor=(0.45,0.25,0.05,0.6),linewidths=0.3))
    for cc in curves: ax.plot(cc[:,0],cc[:,1],cc[:,2],color='crimson',lw=1.8,zorder=10)
    ax.set_xlim(lo[0],hi[0]); ax.set_ylim(lo[1],hi[1]); ax.set_zlim(lo[2]-0.2,hi[2]+0.2)
    ax.set_box_aspect((hi-lo)+np.array([0,0,0.4])); ax.view_init(elev=38 if k==0 else 80,azim=-60); ax.set_axis_off(); ax.set_title(title,fontsize=10)
plt.tight_layout(); plt.savefig(sys.argv[4],dpi=110)
