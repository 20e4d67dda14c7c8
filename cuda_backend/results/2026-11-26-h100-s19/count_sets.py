import numpy as np, sys
from scipy.spatial import Delaunay
rng=np.random.default_rng(1)
n=int(sys.argv[1]) if len(sys.argv)>1 else 1<<20
dist=sys.argv[2] if len(sys.argv)>2 else 'uniform'
if dist=='uniform': P=rng.random((n,2))
else:
    # kuzmin: radial cdf r = sqrt(u^-2 -1)... standard kuzmin disk: M(r)=1-1/sqrt(1+r^2)
    u=rng.random(n); r=np.sqrt(1/(1-u)**2-1); th=rng.random(n)*2*np.pi
    P=np.c_[r*np.cos(th), r*np.sin(th)]
spb=3.5
G=int(np.ceil(np.sqrt(n/spb)))
if dist=='uniform':
    cx=np.minimum((P[:,0]*G).astype(int),G-1); cy=np.minimum((P[:,1]*G).astype(int),G-1)
else:
    qx=np.quantile(P[:,0],np.linspace(0,1,G+1)); qy=np.quantile(P[:,1],np.linspace(0,1,G+1))
    cx=np.clip(np.searchsorted(qx,P[:,0],side='right')-1,0,G-1); cy=np.clip(np.searchsorted(qy,P[:,1],side='right')-1,0,G-1)
cell=cy*G+cx
order=np.argsort(cell,kind='stable'); P=P[order]; cell=cell[order]
starts=np.searchsorted(cell,np.arange(G*G+1))
local=np.arange(n)-starts[cell]
cnt=(starts[1:]-starts[:-1])[cell]
T=Delaunay(P).simplices
deg=np.bincount(T.ravel(),minlength=n)
def evaluate(name,E):
    e=E[T]; k=e.sum(1)
    ph0=deg[E].sum()+E.sum()  # apex searches + NN
    T0=(k==0).sum()
    # phase-1 site searches: its triangles with no E vertex
    s1=np.bincount(T[k==0].ravel(),minlength=n)
    # E-neighbours count of each non-E site (posts): each E-vertex triangle adjacency
    # edges
    edges=np.vstack([T[:,[0,1]],T[:,[1,2]],T[:,[2,0]]]); edges=np.sort(edges,1); edges=np.unique(edges,axis=0)
    en=np.bincount(edges[E[edges[:,0]],1],minlength=n)+np.bincount(edges[E[edges[:,1]],0],minlength=n)
    noE=(~E)&(en==0)
    over=(~E)&(en>5)
    ph1=s1[~E].sum()+noE.sum()
    print(f"{name:28s} |E|/n {E.mean():.3f} phase0 searches/n {ph0/n:.3f} phase1 {ph1/n:.3f} total {(ph0+ph1)/n:.3f} T0/n {T0/n:.3f} ph1 per site mean {s1[~E].mean():.2f} p99 {np.percentile(s1[~E],99):.0f} noE {noE.mean():.4f} over5 {over.mean():.4f}")
evaluate('parity',(np.arange(n)&1)==0)
evaluate('first per cell',local==0)
evaluate('first, and 3rd+',(local==0)|(local==2)|(local==4)|(local==6))
evaluate('local even (cell parity)',(local&1)==0)
# checkerboard variants
cxs=cell%G; cys=cell//G
evaluate('first per cell + 2nd in (cx+cy) even',(local==0)|((local==1)&(((cxs+cys)&1)==0)))
evaluate('first per cell + 2nd if cnt>=4',(local==0)|((local==1)&(cnt>=5)))
# greedy maximal independent set on the true DT (upper bound on what a geometric rule can get)
import scipy.sparse as sp
edges=np.vstack([T[:,[0,1]],T[:,[1,2]],T[:,[2,0]]])
A=sp.coo_matrix((np.ones(len(edges)),(edges[:,0],edges[:,1])),shape=(n,n)).tocsr(); A=A+A.T
# Luby-style: priority random, in E if smaller than all neighbours, iterate
pri=rng.random(n); E=np.zeros(n,bool); alive=np.ones(n,bool)
indptr,ind=A.indptr,A.indices
for it in range(30):
    p=np.where(alive,pri,np.inf)
    nbmin=np.minimum.reduceat(p[ind],indptr[:-1])
    win=alive&(p<nbmin)
    E|=win
    kill=win.copy(); kill[ind[np.repeat(win,np.diff(indptr))]]=True
    alive&=~kill
    if not alive.any(): break
evaluate('greedy MIS (true DT)',E)
# one round of Luby only
p=pri; nbmin=np.minimum.reduceat(p[ind],indptr[:-1]); evaluate('local minima (1 round)',p<nbmin)
