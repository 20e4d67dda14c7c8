# Instructions and stall samples by source file and line, from an ncu source export (cuda,sass CSV, xz):
#   python3 source_lines.py callN-cuda-sass.csv.xz
import csv,collections,sys
rows=list(csv.reader(__import__('lzma').open(sys.argv[1],'rt')))
f=None; hdr=None; out=[]
for r in rows:
    if not r: continue
    if r[0]=='File Path': f=r[1].split('/')[-1]; continue
    if r[0]=='Line No': hdr=r; continue
    if r[0]=='Function Name': continue
    if r[0]=='' : continue  # sass rows
    try: ln=int(r[0])
    except: continue
    g=lambda k:int(r[k]) if r[k] not in ('','-') else 0
    try: ins=g(7); thr=g(8); samp=g(4); d={"Source":r[1]}
    except Exception: continue
    if ins or samp: out.append((f,ln,d['Source'][:90],ins,thr,samp))
tot_i=sum(o[3] for o in out); tot_s=sum(o[5] for o in out); tot_t=sum(o[4] for o in out)
print('total warp inst %.3g thread inst %.3g (avg lanes %.2f) samples %d'%(tot_i,tot_t,tot_t/tot_i,tot_s))
byfile=collections.Counter(); byfs=collections.Counter()
for o in out: byfile[o[0]]+=o[3]; byfs[o[0]]+=o[5]
for k,v in byfile.most_common(): print('  %-25s inst %5.1f%%  samples %5.1f%%'%(k,100*v/tot_i,100*byfs[k]/tot_s))
print('top lines by samples')
for o in sorted(out,key=lambda o:-o[5])[:45]:
    print('%5.1f%% s %5.1f%% i lanes %5.1f  %s:%d  %s'%(100*o[5]/tot_s,100*o[3]/tot_i,o[4]/max(o[3],1),o[0],o[1],o[2]))
