# The first phase's lock-step cost from per-site work counted on the CPU (expanse-bench-star-work
# with star-work-dump.diff applied: --dump-work /tmp/work writes each local site's work and its
# cell's occupancy, uint32 in the kernels' cell order). Session 18's numbers come from this.
#   /usr/bin/python3 work_model.py /tmp/work kuzmin:4096 uniform:1024 gaussian:4096
# (DIST:CAP, CAP the first pass's budget at 4096^2: a site past it stops there.)
import sys, numpy as np
prefix = sys.argv[1]
for arg in sys.argv[2:]:
    dist, cap = arg.split(':'); cap = float(cap)
    work = np.fromfile('%s.%s.16777216.bin' % (prefix, dist), dtype=np.uint32).astype(np.float64)
    even = np.minimum(work[0::2], cap) + 8  # the first phase's sites; + a fixed cost a site
    n = len(even) // 128 * 128; even = even[:n]
    warp = even.reshape(-1, 32).max(axis=1)
    print('%s: lane mean %.1f, warp mean %.1f (a warp lasts as long as its busiest lane)' % (dist, even.mean(), warp.mean()))
    for threads in (128, 64, 32):  # a block holds its slot until its slowest warp is done
        print('   blocks of %3d: block mean per warp %.1f' % (threads, warp.reshape(-1, threads // 32).max(axis=1).mean()))
    blocks = warp.reshape(-1, 4).max(axis=1)
    print('   blocks of 128, mean cost by twentieth of the cell order:', ' '.join('%.0f' % x.mean() for x in np.array_split(blocks, 20)))
    for t in (512, 1024, 2048):
        print('   warps whose busiest lane passes %4d: %.3f of the warps, %.3f of the warp time' % (t, (warp > t).mean(), warp[warp > t].sum() / warp.sum()))
    try:
        occ = np.fromfile('%s.%s.16777216.occ' % (prefix, dist), dtype=np.uint32)[0::2][:n]
    except FileNotFoundError:
        continue
    order = np.argsort(np.floor(np.log2(np.maximum(occ, 1))), kind='stable')
    print('   sites sorted by their cell occupancy class: warp mean %.1f' % even[order].reshape(-1, 32).max(axis=1).mean())
    for k in (16, 64):
        out = np.where(occ >= k, 8.0, even)
        print('   sites of cells of %d or more left out: warp mean %.1f (their work %.0f units)' % (k, out.reshape(-1, 32).max(axis=1).mean(), even[occ >= k].sum()))
