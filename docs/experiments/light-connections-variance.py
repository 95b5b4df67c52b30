#!/usr/bin/env python3
"""Throwaway estimate behind light-connections.md: at five points of cornell-measured's ceiling,
the per-sample variance of the one-bounce indirect light (x1 -> y1 -> lamp) by (a) a cosine
bounce at x1 then light sampling at y1, (b) a light vertex y1 (lamp point, cosine direction)
connected to x1, and their power-heuristic combination, with independent numbers. Ray casting
through Mitsuba 3 (llvm_ad_rgb) on the same OBJ. Run from the repository root:
    python3 docs/experiments/light-connections-variance.py
"""
import sys, numpy as np, mitsuba as mi
sys.path.insert(0, 'tools')
mi.set_variant('llvm_ad_rgb')
from path_time_to_error import mitsuba_scene
import os
os.makedirs('target/bench/light-connections', exist_ok=True)
scene = mitsuba_scene(mi, 'scenes/cornell-measured/cornell.obj', 'scenes/cornell-measured/cornell.mtl',
    {"eye":[278,273,-800],"target":[278,273,0],"up":[0,1,0],"fov":39.3}, 64, 64, 'target/bench/light-connections')
rng = np.random.default_rng(1)
LE = np.array([17,12,4.]); A = 130*105.
def cast(o, d):
    ray = mi.Ray3f(mi.Point3f(o[:,0],o[:,1],o[:,2]), mi.Vector3f(d[:,0],d[:,1],d[:,2]))
    si = scene.ray_intersect(ray)
    ctx = mi.BSDFContext()
    valid = np.array(si.is_valid())
    p = np.stack([np.array(si.p.x),np.array(si.p.y),np.array(si.p.z)],1)
    n = np.stack([np.array(si.n.x),np.array(si.n.y),np.array(si.n.z)],1)
    # albedo via eval at normal incidence: eval = rho/pi * cos
    si.wi = mi.Vector3f(0,0,1)
    refl = si.bsdf().eval(ctx, si, mi.Vector3f(0,0,1))
    rho = np.stack([np.array(refl.x),np.array(refl.y),np.array(refl.z)],1)*np.pi
    t = np.array(si.t)
    return valid, p, n, rho, t
def visible(a, b):
    d = b - a; dist = np.linalg.norm(d,axis=1); d = d/dist[:,None]
    ray = mi.Ray3f(mi.Point3f(a[:,0],a[:,1],a[:,2]), mi.Vector3f(d[:,0],d[:,1],d[:,2])); ray.maxt = mi.Float(dist*(1-1e-3))
    ray.o = ray.o + ray.d*1e-3
    return ~np.array(scene.ray_test(ray))
def cos_hemi(u, n):
    r = np.sqrt(u[:,0]); ph = 2*np.pi*u[:,1]
    x = r*np.cos(ph); y = r*np.sin(ph); z = np.sqrt(np.maximum(0,1-u[:,0]))
    # build basis
    t = np.where(np.abs(n[:,0:1])>0.9, np.array([[0,1,0.]]), np.array([[1,0,0.]]))
    b1 = np.cross(n, t); b1 /= np.linalg.norm(b1,axis=1)[:,None]; b2 = np.cross(n,b1)
    return x[:,None]*b1 + y[:,None]*b2 + z[:,None]*n, z
def lamp_pt(u):
    return np.stack([213+130*u[:,0], np.full(len(u),548.7), 227+105*u[:,1]],1)
M = 200000
down = np.array([0,-1,0.])
for X in [(278,548.8,280),(150,548.8,150),(450,548.8,450),(278,548.8,100),(50,548.8,500)]:
    x1 = np.tile(np.array(X,float),(M,1)); n1 = np.tile(down,(M,1))
    rho1 = np.array([0.74,0.74,0.74])  # placeholder; same for both strategies
    # (a) BSDF at x1 then NEE at x2
    d, c1 = cos_hemi(rng.random((M,2)), n1)
    ok, x2, n2, rho2, t = cast(x1 + 1e-2*d, d)
    n2 = np.where((np.sum(n2*d,1)>0)[:,None], -n2, n2)
    y0 = lamp_pt(rng.random((M,2)))
    w = y0 - x2; r2 = np.sum(w*w,1); w /= np.sqrt(r2)[:,None]
    cos2 = np.sum(n2*w,1); cos0 = w[:,1]
    vis = visible(x2 + n2*1e-2, y0)
    ok = ok & (cos2>0) & (cos0>0) & vis & (x2[:,1] < 548.5)
    va = np.where(ok[:,None], rho2/np.pi*LE*cos2[:,None]*cos0[:,None]/r2[:,None]*A, 0)
    # densities of that path (area measure at x2 then y0)
    pa_a = (c1/np.pi) * np.abs(np.sum(n2*d,1)) / t**2 / A
    pb_a = (1/A) * (np.maximum(cos0,0)/np.pi) * np.maximum(cos2,0) / r2
    # (b) connection: y0 on lamp, cos-sample down, hit y1, connect to x1
    y0b = lamp_pt(rng.random((M,2)))
    db, cb0 = cos_hemi(rng.random((M,2)), np.tile(down,(M,1)))
    okb, y1, ny1, rhoy, tb = cast(y0b + 1e-2*db, db)
    ny1 = np.where((np.sum(ny1*db,1)>0)[:,None], -ny1, ny1)
    cin = np.abs(np.sum(ny1*db,1))
    v = x1 - y1; d2 = np.sum(v*v,1); v /= np.sqrt(d2)[:,None]
    cy = np.sum(ny1*v,1); cx = -np.sum(n1*v,1) * -1  # cos at x1: n1 . (y1-x1)
    cx = np.sum(n1*(-v),1)
    visb = visible(y1 + ny1*1e-2, x1 + down*1e-2)
    okb = okb & (cy>0) & (cx>0) & visb & (y1[:,1] < 548.5)
    G = np.maximum(cx,0)*np.maximum(cy,0)/d2
    vb = np.where(okb[:,None], rhoy/np.pi*LE*np.pi*A*G[:,None], 0)   # times rho1/pi*pi? see below
    # (a) estimates L1/rho1*... : va = rho2/pi Le G(x2,y0) A  (rho1 factored out: f1 cos/pdf = rho1)
    # (b) estimate same quantity: f1 = rho1/pi -> divide by rho1 => vb/pi
    vb = vb/np.pi
    pa_b = (cx/np.pi) * np.maximum(cy,0) / d2 / A
    pb_b = (1/A) * (cb0/np.pi) * cin / tb**2
    wa = pa_a**2/(pa_a**2+pb_a**2+1e-300); wb = pb_b**2/(pa_b**2+pb_b**2+1e-300)
    g = lambda v: v[:,1]
    ma, mb = g(va).mean(), g(vb).mean()
    comb = wa*g(va) + wb*g(vb)
    print(X, "mean a %.5f b %.5f comb %.5f | var a %.3e b %.3e comb %.3e | ratio comb/a %.3f  b/a %.3f" % (ma, mb, comb.mean(), g(va).var(), g(vb).var(), (wa*g(va)).var()+(wb*g(vb)).var(), ((wa*g(va)).var()+(wb*g(vb)).var())/g(va).var(), g(vb).var()/g(va).var()))
