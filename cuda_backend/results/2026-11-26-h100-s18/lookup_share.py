# Samples and instructions of the quantile cell lookups (device_geometry.cuh's QuantileGuide and
# GridView index functions, quantile_guide.hpp) in an ncu source export, against the whole kernel:
#   python3 lookup_share.py call2-cuda-sass-kuzmin.csv.xz
import csv, lzma, sys
rows = list(csv.reader(lzma.open(sys.argv[1], 'rt')))
f = None; total_s = total_i = 0; parts = {}
for r in rows:
    if not r: continue
    if r[0] == 'File Path': f = r[1].split('/')[-1]; continue
    try: ln = int(r[0])
    except ValueError: continue
    g = lambda k: int(r[k]) if r[k] not in ('', '-') else 0
    try: ins, samp = g(7), g(4)
    except (ValueError, IndexError): continue  # a source line whose text split the row
    total_s += samp; total_i += ins
    key = None
    if f == 'quantile_guide.hpp': key = 'quantile_guide.hpp'
    elif f == 'device_geometry.cuh' and 96 <= ln <= 160: key = 'device_geometry.cuh:%d' % ln
    if key:
        s, i = parts.get(key, (0, 0)); parts[key] = (s + samp, i + ins)
ls = sum(s for s, _ in parts.values()); li = sum(i for _, i in parts.values())
print('samples %d, lookups %d (%.1f%%); instructions %.3g, lookups %.3g (%.1f%%)' % (total_s, ls, 100 * ls / total_s, total_i, li, 100 * li / total_i))
for k, (s, i) in sorted(parts.items(), key=lambda kv: -kv[1][0])[:8]: print('  %-28s samples %5.1f%%' % (k, 100 * s / total_s))
