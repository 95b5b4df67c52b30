"""Path-like rays of a realistic ladder scene: camera rays (pixel order, SPP per pixel), then
cosine bounces from each hit (pixel order, independent numbers), for DEPTH bounces; and shadow
rays from every bounce origin toward the map's sun. Traced with vkrt trace to find the hits."""
import sys, subprocess, numpy as np
obj, eye, target, fov, W, H, SPP, DEPTH = sys.argv[1], np.array(eval(sys.argv[2]),float), np.array(eval(sys.argv[3]),float), float(sys.argv[4]), 320, 240, int(sys.argv[5]), int(sys.argv[6])
V=[];F=[]
for line in open(obj, encoding='latin-1'):
    p=line.split()
    if not p: continue
    if p[0]=='v': V.append([float(x) for x in p[1:4]])
    elif p[0]=='f':
        idx=[int(t.split('/')[0]) for t in p[1:]]; idx=[i-1 if i>0 else len(V)+i for i in idx]
        for k in range(1,len(idx)-1): F.append([idx[0],idx[k],idx[k+1]])
V=np.array(V,np.float32); T=V[np.array(F)].astype(np.float64)
Nrm=np.cross(T[:,1]-T[:,0],T[:,2]-T[:,0]); Nrm/=np.linalg.norm(Nrm,axis=1)[:,None]
scale=np.abs(V).max()
rng=np.random.default_rng(1)
fwd=(target-eye); fwd/=np.linalg.norm(fwd); right=np.cross(fwd,[0,1,0]); right/=np.linalg.norm(right); up=np.cross(right,fwd)
th=np.tan(np.radians(fov)/2)
j,i=np.mgrid[0:H,0:W]; i=np.repeat(i.ravel(),SPP); j=np.repeat(j.ravel(),SPP)
x=((i+rng.random(len(i)))/W*2-1)*th*W/H; y=(1-(j+rng.random(len(j)))/H*2)*th
D=fwd+x[:,None]*right+y[:,None]*up; D/=np.linalg.norm(D,axis=1)[:,None]
O=np.broadcast_to(eye,D.shape).copy()
def pack(O,D):
    R=np.zeros((len(D),8),np.float32); R[:,0:3]=O; R[:,4:7]=D; R[:,7]=np.inf; return R
def trace(R):
    np.save('/tmp/wf/r.npy',R); subprocess.run(['/work/main/target/release/vkrt','trace',obj,'--rays','/tmp/wf/r.npy','-o','/tmp/wf/h.npy','--order','auto'],check=True,capture_output=True)
    return np.load('/tmp/wf/h.npy')
# the sun: u 0.3, v 0.306 in Mitsuba's lat-long (u = atan2(x, -z) / 2pi, v = acos(y) / pi)
phi=2*np.pi*0.3; thv=np.pi*0.306
sun=np.array([np.sin(thv)*np.sin(phi), np.cos(thv), -np.sin(thv)*np.cos(phi)])
bounces=[];shadows=[]
for d in range(DEPTH+1):
    h=trace(pack(O,D)); hit=h['prim']!=0xFFFFFFFF
    O,D,h=O[hit],D[hit],h[hit]
    P=O+D*h['t'][:,None].astype(np.float64); n=Nrm[h['prim']].copy(); flip=(n*D).sum(1)>0; n[flip]*=-1
    P=P+n*1e-4*scale
    sh=(n@sun)>0; shadows.append(pack(P[sh],np.broadcast_to(sun,P[sh].shape)))
    if d==DEPTH: break
    u1=rng.random(len(P)); u2=rng.random(len(P)); r=np.sqrt(u1); ph=2*np.pi*u2
    a=np.where(np.abs(n[:,0:1])>0.9,np.array([[0,1,0]]),np.array([[1,0,0]])); t1=np.cross(a,n); t1/=np.linalg.norm(t1,axis=1)[:,None]; b1=np.cross(n,t1)
    D=t1*(r*np.cos(ph))[:,None]+b1*(r*np.sin(ph))[:,None]+n*np.sqrt(1-u1)[:,None]; O=P
    bounces.append(pack(O,D))
np.save('/tmp/wf/bounce.npy',np.concatenate(bounces)); np.save('/tmp/wf/shadow.npy',np.concatenate(shadows))
print('bounce',sum(len(b) for b in bounces),'shadow',sum(len(s) for s in shadows))
