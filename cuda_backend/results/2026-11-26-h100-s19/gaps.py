import numpy as np, sys
from scipy.spatial import Delaunay
rng=np.random.default_rng(1)
n=1<<18
P=rng.random((n,2))
spb=3.5; G=int(np.ceil(np.sqrt(n/spb)))
cx=np.minimum((P[:,0]*G).astype(int),G-1); cy=np.minimum((P[:,1]*G).astype(int),G-1)
order=np.argsort(cy*G+cx,kind='stable'); P=P[order]
D=Delaunay(P); T=D.simplices
odd=(np.arange(n)&1)==1
# per site: list of triangles around it in ccw order -> use vertex_neighbor_vertices + orientation sort
indptr,ind=D.vertex_neighbor_vertices
sites_searches=[]; gaps=[]
allodd=set(map(tuple,np.sort(T[odd[T].all(1)],1)))
for s in np.nonzero(odd)[0]:
    nb=ind[indptr[s]:indptr[s+1]]
    ang=np.arctan2(P[nb,1]-P[s,1],P[nb,0]-P[s,0]); nb=nb[np.argsort(ang)]
    k=len(nb)
    miss=[]
    for t in range(k):
        a,b=nb[t],nb[(t+1)%k]
        tri=tuple(sorted((s,a,b)))
        miss.append(tri in allodd)  # hull triangles: may not exist; ignore (few)
    miss=np.array(miss)
    sites_searches.append(miss.sum())
    if miss.all(): gaps.append(k); continue
    # runs of True cyclic
    r=np.roll(miss,-int(np.argmin(miss)))
    run=0
    for m in r:
        if m: run+=1
        elif run: gaps.append(run); run=0
    if run: gaps.append(run)
ss=np.array(sites_searches); g=np.array(gaps)
def lock(x):
    m=len(x)//32*32; return x[:m].reshape(-1,32).max(1).sum()/m
print('odd sites',len(ss),'searches/site',ss.mean(),'zero-search share',(ss==0).mean())
print('site-per-lane lockstep per lane',lock(ss),'efficiency',ss.mean()/lock(ss))
print('gaps per odd site',len(g)/len(ss),'gap len hist',np.bincount(g)[:8]/len(g))
print('gap-per-lane lockstep per lane',lock(g),'efficiency',g.mean()/lock(g))
print('warp-steps: site-per-lane',lock(ss)*len(ss)/32,'gap-per-lane',lock(g)*len(g)/32)
