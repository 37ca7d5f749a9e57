#!/usr/bin/python3
# The matchability ceiling of a rendered rover pair (docs/app.md "Worlds it was not tuned
# on"): for image-1 pixels on a 6 px grid that image 2 sees (true range of both frames
# within 1 %), the NCC of a WINDOW x WINDOW template (default 11, the matcher's) with the
# image-2 patch at the TRUE correspondence under the TRUE local affine map (from the true
# ranges of the pixel's right and lower neighbours). A matcher that accepts NCC >= 0.8
# can at best find the share printed. Ground-side diagnostic (Debian python3-numpy,
# python3-pil); the input is `vtm-sim render SCENARIO DIR --frames 0,1`.
# --planes adds the same NCC under plane-induced warps instead of the true affine map:
# the level ground (the matcher's terrain hypothesis), planes tilted 15/30/45 deg from it
# towards camera 1, and the plane facing camera 1 (its fronto-parallel hypothesis), by
# bands of true range / baseline (docs/app.md "Worlds it was not tuned on").
#   tools/scripts/ncc_at_truth.py DIR [WINDOW] [--planes]
import sys, numpy as np
from PIL import Image
def pfm(p):
    f=open(p,'rb'); assert f.readline().strip()==b'Pf'
    w,h=map(int,f.readline().split()); s=float(f.readline())
    a=np.frombuffer(f.read(),dtype='<f4' if s<0 else '>f4').reshape(h,w)
    return np.flipud(a).astype(np.float64)
def quat(w,x,y,z):
    return np.array([[1-2*(y*y+z*z),2*(x*y-w*z),2*(x*z+w*y)],[2*(x*y+w*z),1-2*(x*x+z*z),2*(y*z-w*x)],[2*(x*z-w*y),2*(y*z+w*x),1-2*(x*x+y*y)]])
planes='--planes' in sys.argv[1:]
args=[a for a in sys.argv[1:] if a!='--planes']
if len(args) not in (1, 2):
    sys.exit('usage: ncc_at_truth.py DIR [WINDOW] [--planes]')
d=args[0]
hw=(int(args[1]) if len(args) == 2 else 11)//2
poses={}
for l in open(d+'/camera_poses.txt'):
    if l[0] in '#v': continue
    t=l.split(); poses[int(t[0])]=(np.array(list(map(float,t[3:6]))),quat(*map(float,t[6:10])))
cm=dict(l.split()[:2] for l in open(d+'/mast.cmod') if len(l.split())>=2)
fx,fy,cx,cy=[float(cm[k]) for k in ('fx_px','fy_px','cx_px','cy_px')]
A=np.asarray(Image.open(d+'/mast_000.png').convert('L'),dtype=np.float64)
B=np.asarray(Image.open(d+'/mast_001.png').convert('L'),dtype=np.float64)
rA=pfm(d+'/mast_000_range.pfm'); rB=pfm(d+'/mast_001_range.pfm')
h,w=A.shape
(tA,RA),(tB,RB)=poses[0],poses[1]
def ptA(u,v):
    r=rA[v,u]
    ray=np.array([(u-cx)/fx,(v-cy)/fy,1.0]); ray/=np.linalg.norm(ray)
    return RA@(r*ray)+tA
def projB(X):
    Xb=RB.T@(X-tB)
    if Xb[2]<=0: return None
    return np.array([fx*Xb[0]/Xb[2]+cx, fy*Xb[1]/Xb[2]+cy]), np.linalg.norm(Xb)
def bil(I,x,y):
    x0=np.floor(x).astype(int); y0=np.floor(y).astype(int); ax=x-x0; ay=y-y0
    ok=(x0>=0)&(y0>=0)&(x0<w-1)&(y0<h-1)
    x0=np.clip(x0,0,w-2); y0=np.clip(y0,0,h-2)
    v=I[y0,x0]*(1-ax)*(1-ay)+I[y0,x0+1]*ax*(1-ay)+I[y0+1,x0]*(1-ax)*ay+I[y0+1,x0+1]*ax*ay
    return v, ok
UP=np.array([0,0,-1.0])  # site frame: north, east, down
PLANES=(('level',0),('15 deg',15),('30 deg',30),('45 deg',45),('facing',None))
def rayA(u,v):
    r=np.array([(u-cx)/fx,(v-cy)/fy,1.0]); return RA@(r/np.linalg.norm(r))
def planeJ(X,n,u,v):
    # The local affine map in B of the plane through X with normal n (unit steps in A).
    def hit(uu,vv):
        dd=rayA(uu,vv); den=n@dd
        if abs(den)<1e-12: return None
        q=projB(tA+(n@(X-tA)/den)*dd); return None if q is None else q[0]
    p0,p1,p2=hit(u,v),hit(u+1,v),hit(u,v+1)
    return None if p0 is None or p1 is None or p2 is None else np.column_stack([p1-p0,p2-p0])
def ncc(ta,p,J):
    # NCC of A's template with B warped by J around p; None when J is None or the warped
    # window leaves B.
    if J is None: return None
    bx=p[0]+J[0,0]*ox+J[0,1]*oy; by=p[1]+J[1,0]*ox+J[1,1]*oy
    tb,ok=bil(B,bx,by)
    if not ok.all(): return None
    a=ta-ta.mean(); b=tb-tb.mean()
    return (a*b).sum()/np.sqrt((a*a).sum()*(b*b).sum()+1e-9)
scores=[]; rng=[]; hyp=[]
oy,ox=np.mgrid[-hw:hw+1,-hw:hw+1]
for v in range(hw+2,h-hw-2,6):
    for u in range(hw+2,w-hw-2,6):
        if not (0<rA[v,u]<1e5 and 0<rA[v,u+1]<1e5 and 0<rA[v+1,u]<1e5): continue
        X=ptA(u,v); pb=projB(X)
        if pb is None: continue
        p,rng_b=pb
        if not (hw+2<=p[0]<w-hw-2 and hw+2<=p[1]<h-hw-2): continue
        rb=rB[int(round(p[1])),int(round(p[0]))]
        if not (abs(rb-rng_b)<0.01*rng_b): continue
        px=projB(ptA(u+1,v)); py=projB(ptA(u,v+1))
        if px is None or py is None: continue
        J=np.column_stack([px[0]-p,py[0]-p])
        if abs(np.linalg.det(J))<1/16 or np.abs(J).max()>8: continue
        ta=A[v-hw:v+hw+1,u-hw:u+hw+1]
        if ta.std()<2: continue
        s=ncc(ta,p,J)
        if s is None: continue
        scores.append(s); rng.append(rA[v,u])
        if planes:
            X=ptA(u,v); ray=rayA(u,v); toward=-ray.copy(); toward[2]=0; toward/=np.linalg.norm(toward)
            row=[]
            for name,deg in PLANES:
                n=-ray if deg is None else np.cos(np.radians(deg))*UP+np.sin(np.radians(deg))*toward
                q=ncc(ta,p,planeJ(X,n,u,v))
                row.append(-1.0 if q is None else q)  # a warp that leaves B: no match
            hyp.append(row)
s=np.array(scores); r=np.array(rng)
print('%s: %d points, NCC at truth (true affine, window %d): median %.3f, >0.8 %.1f%%, >0.6 %.1f%%'%(d,len(s),2*hw+1,np.median(s),100*(s>0.8).mean(),100*(s>0.6).mean()))
for lo,hi in ((0,10),(10,25),(25,60),(60,300)):
    m=(r>=lo)&(r<hi)
    if m.sum(): print('  range %3d-%3d m: %5d pts, median NCC %.3f, >0.8 %.1f%%'%(lo,hi,m.sum(),np.median(s[m]),100*(s[m]>0.8).mean()))
if planes and hyp:
    hv=np.array(hyp); base=np.linalg.norm(tB-tA)
    print('  by true range / baseline (%.2f m): share of points with NCC >= 0.8' % base)
    print('    band        points  true affine  ' + '  '.join('%8s' % n for n,_ in PLANES))
    for lo,hi in ((0,1.5),(1.5,2.5),(2.5,4),(4,8),(8,1e9)):
        m=(r/base>=lo)&(r/base<hi)
        if m.sum(): print('    %4.1f-%-5s %6d  %10.0f%%  '%(lo,'inf' if hi>1e8 else '%g'%hi,m.sum(),100*(s[m]>=0.8).mean()) + '  '.join('%7.0f%%' % (100*(hv[m,i]>=0.8).mean()) for i in range(len(PLANES))))
