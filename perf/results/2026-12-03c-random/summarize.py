#!/usr/bin/env python3
# The summary of an ab.sh folder: per cell (scene, kind, path) the median over rounds of B / A
# (Mrays/s, same round), then per kind and path the median, min and max over the cells.
import sys,re,glob,statistics as st,collections
d=sys.argv[1]
vals=collections.defaultdict(lambda: collections.defaultdict(dict))
errs=0
for f in glob.glob(d+'/[AB]-*.log'):
    w,r=f.split('/')[-1][:-4].split('-')
    for line in open(f):
        m=re.match(r'(\S+)\s+(\w+)\s+bvh-sah\s+(\w+)\s+([\d.]+) Mrays/s.*err (\d+)',line)
        if m:
            vals[(m.group(1),m.group(2),m.group(3))][w][int(r)]=float(m.group(4)); errs+=int(m.group(5))
bykind=collections.defaultdict(list)
for k in sorted(vals):
    a=vals[k]['A']; b=vals[k]['B']
    rs=[b[r]/a[r] for r in a if r in b]
    med=st.median(rs)
    bykind[(k[1],k[2])].append((med,k[0]))
    print(f"{k[0]:24s} {k[1]:8s} {k[2]:7s} A {st.median(a.values()):7.2f} B {st.median(b.values()):7.2f}  B/A med {med:.3f}  [{min(rs):.3f}-{max(rs):.3f}] n={len(rs)}")
for kk,v in sorted(bykind.items()):
    ms=[x[0] for x in v]
    print(f"{kk[0]:8s} {kk[1]:7s} median {st.median(ms):.3f} min {min(ms):.3f} ({min(v)[1]}) max {max(ms):.3f} ({max(v)[1]})")
print("errors vs scalar (sum):",errs)
