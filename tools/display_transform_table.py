#!/usr/bin/env python3
"""The table of docs/experiments/display-transform.md: for linear .pfm renders, the automatic
exposure (log-average luminance to 0.18, capped so that the 95th percentile of the lit
pixels' luminance stays at or below 1) and what clamp and PBR Neutral do at EV 0 and at it.
The same arithmetic as host/output/display.rs. Usage: display_transform_table.py IMAGE.pfm..."""
import struct,sys,math
def pfm(f):
    d=open(f,'rb').read(); parts=d.split(b'\n',3); w,h=map(int,parts[1].split()); n=w*h*3
    return struct.unpack('<%df'%n,parts[3][:4*n])
def neutral(c):
    x=min(c); off = x-6.25*x*x if x<0.08 else 0.04
    c=[v-off for v in c]; peak=max(c)
    if peak<0.76: return [min(max(v,0),1) for v in c]
    d=0.24; npk=1-d*d/(peak+d-0.76); c=[v*npk/peak for v in c]
    g=1-1/(0.15*(peak-npk)+1); return [min(max(v+(npk-v)*g,0),1) for v in c]
print("| scene | integrator | auto EV | values >= 1 at EV 0 | at auto EV | pixels >= 0.99 after neutral, EV 0 | after neutral, auto | mean display value EV 0 + neutral | auto + neutral |")
print("|---|---|---:|---:|---:|---:|---:|---:|---:|")
for f in sys.argv[1:]:
    v=pfm(f); px=[v[i:i+3] for i in range(0,len(v),3)]
    lum=[0.2126*p[0]+0.7152*p[1]+0.0722*p[2] for p in px]; pos=[l for l in lum if l>1e-6]
    key=math.exp(sum(math.log(l) for l in pos)/len(pos))
    p95=sorted(pos)[int(0.95*(len(pos)-1))]; s=min(0.18/key, 1/p95)
    def frac(scale): return 100*sum(1 for x in v if x*scale>=1)/len(v)
    def sat(scale):
        out=[neutral([c*scale for c in p]) for p in px]
        return 100*sum(1 for o in out if max(o)>=0.99)/len(out), sum(sum(o) for o in out)/(3*len(out))
    s0=sat(1); sa=sat(s)
    name=f.rsplit('-',1)[0]; integ={'w':'Whitted','p':'path'}[f[-5]]
    print(f"| {name} | {integ} | {math.log2(s):+.1f} | {frac(1):.1f} % | {frac(s):.1f} % | {s0[0]:.1f} % | {sa[0]:.1f} % | {s0[1]:.3f} | {sa[1]:.3f} |")
