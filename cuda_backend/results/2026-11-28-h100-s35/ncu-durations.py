# Session 35: kernel durations from an ncu CSV (gpu__time_duration), the last triangulation in order
# then summed by kernel: python3 ncu-durations.py FILE.csv.xz [KERNELS]
import csv,sys,collections,re,lzma
lines=lzma.open(sys.argv[1],'rt').read().splitlines()
i=[k for k,l in enumerate(lines) if l.startswith('"ID"')][0]
rows=list(csv.reader(lines[i:]))
h=rows[0]; c={k:i for i,k in enumerate(h)}
seq=[]
for r in rows[1:]:
  if len(r)<len(h) or r[c['Metric Name']]!='gpu__time_duration.sum': continue
  name=re.sub(r'\(.*','',r[c['Kernel Name']])[:70]
  name=re.sub(r'^void ','',name)
  v=float(r[c['Metric Value']].replace(',',''))
  unit=r[c['Metric Unit']]
  v = v/1e3 if unit=="us" else v/1e6 if unit=="ns" else v
  seq.append((name,v,r[c['Grid Size']]))
starts=[i for i,(n,v,g) in enumerate(seq) if 'morton_kernel' in n or 'short_key_kernel' in n]
print('starts',starts,'of',len(seq))
s=starts[-1]
end=int(sys.argv[2]) if len(sys.argv)>2 else 45
for i,(n,v,g) in enumerate(seq[s:s+end]): print('%3d %8.3f ms  %s %s'%(i,v,n,g))
tot=collections.defaultdict(float); cnt=collections.Counter()
for n,v,g in seq[s:]: tot[n]+=v; cnt[n]+=1
print('total', sum(tot.values()))
for k,v in sorted(tot.items(), key=lambda x:-x[1])[:30]: print('%9.3f ms %4d  %s'%(v,cnt[k],k))
