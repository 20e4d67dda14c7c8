# Kernel durations of the pipeline's timed repetition from call 8's ncu output (CSV rows mixed
# with the benchmark's own output): from the last launch of the preparation's first kernel on.
#   python3 kernel_times.py call8-ncu-kuzmin.csv
import csv, sys, collections
for path in sys.argv[1:]:
    lines = [l for l in open(path) if l.startswith('"')]
    rows = list(csv.reader(lines))
    h = rows[0]; ki = h.index('Kernel Name'); vi = h.index('Metric Value'); ui = h.index('Metric Unit')
    seq = []
    for r in rows[1:]:
        if r[0] == 'ID': continue
        v = float(r[vi].replace(',', '')); u = r[ui]
        ms = v / 1e6 if u in ('ns', 'nsecond') else v / 1e3 if u in ('us', 'usecond') else v
        name = r[ki].split('(')[0].split('::')[-1].split('<')[0]
        seq.append((name, ms))
    starts = [i for i, (k, _) in enumerate(seq) if k in ('short_key_kernel', 'morton_kernel')]
    tail = seq[starts[-1]:]
    agg = collections.OrderedDict(); cnt = collections.Counter()
    for k, ms in tail:
        agg[k] = agg.get(k, 0) + ms; cnt[k] += 1
    print('==', path.split('/')[-1], 'launches', len(seq), 'pipeline repetition', len(tail), 'ms %.3f' % sum(agg.values()))
    for k, ms in agg.items(): print('  %-44s x%-3d %.3f' % (k, cnt[k], ms))
