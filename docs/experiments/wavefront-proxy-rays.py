"""Path-tracer-like ray sets for a Cornell box OBJ (tried-and-not-kept.md, "A wavefront split"):
bounce rays from random surface points (by area) in cosine directions about the normal that faces
the room, and shadow rays from the same points to a patch under the ceiling's centre. Writes
/tmp/wf/bounce.npy and /tmp/wf/shadow.npy in `vkrt trace`'s ray layout.
Usage: wavefront-proxy-rays.py SCENE.obj RAYS"""
import os
import sys

import numpy as np

os.makedirs('/tmp/wf', exist_ok=True)
obj = sys.argv[1]; n = int(sys.argv[2]); seed = 1
V=[]; F=[]
for line in open(obj):
    p=line.split()
    if not p: continue
    if p[0]=='v': V.append([float(x) for x in p[1:4]])
    elif p[0]=='f':
        idx=[int(t.split('/')[0]) for t in p[1:]]
        idx=[i-1 if i>0 else len(V)+i for i in idx]
        for k in range(1,len(idx)-1): F.append([idx[0],idx[k],idx[k+1]])
V=np.array(V); T=V[np.array(F)]
e1=T[:,1]-T[:,0]; e2=T[:,2]-T[:,0]; N=np.cross(e1,e2); A=np.linalg.norm(N,axis=1)/2; N/=np.linalg.norm(N,axis=1)[:,None]
c=V.mean(0)
rng=np.random.default_rng(seed)
def surf(m):
    t=rng.choice(len(T),m,p=A/A.sum()); r1=rng.random(m); r2=rng.random(m); s=np.sqrt(r1)
    P=T[t,0]*(1-s)[:,None]+T[t,1]*(s*(1-r2))[:,None]+T[t,2]*(s*r2)[:,None]
    nn=N[t].copy(); flip=((c-P)*nn).sum(1)<0; nn[flip]*=-1  # face the room's centre
    return P,nn,t
P,nn,_=surf(n)
# cosine directions
u1=rng.random(n); u2=rng.random(n); r=np.sqrt(u1); ph=2*np.pi*u2
lx=r*np.cos(ph); ly=r*np.sin(ph); lz=np.sqrt(1-u1)
a=np.where(np.abs(nn[:,0:1])>0.9, np.array([[0,1,0]]), np.array([[1,0,0]]))
tt=np.cross(a,nn); tt/=np.linalg.norm(tt,axis=1)[:,None]; bb=np.cross(nn,tt)
D=tt*lx[:,None]+bb*ly[:,None]+nn*lz[:,None]
O=P+nn*1e-4
R=np.zeros((n,8),np.float32); R[:,0:3]=O; R[:,3]=0; R[:,4:7]=D; R[:,7]=np.inf
np.save('/tmp/wf/bounce.npy',R)
# shadow rays to random points near the ceiling light (the top 1 % of y, centre quarter)
ymax=V[:,1].max(); lo=V.min(0); hi=V.max(0)
L=np.stack([lo[0]+(hi[0]-lo[0])*(0.4+0.2*rng.random(n)), np.full(n,ymax-1e-3), lo[2]+(hi[2]-lo[2])*(0.4+0.2*rng.random(n))],1)
d=L-O; dist=np.linalg.norm(d,axis=1); d/=dist[:,None]
S=np.zeros((n,8),np.float32); S[:,0:3]=O; S[:,4:7]=d; S[:,7]=dist*0.999
np.save('/tmp/wf/shadow.npy',S)
print(len(T),'triangles', n,'rays')
