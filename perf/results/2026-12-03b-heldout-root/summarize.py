import sys,re,glob,statistics,collections
d=sys.argv[1]
runs=collections.defaultdict(dict)  # (w,n) -> {(cell,kind,struct,path): mrays}
errs=collections.Counter()
for f in sorted(glob.glob(d+'/[AB]-*.log')):
    w,n=f.split('/')[-1][:-4].split('-')
    for line in open(f):
        m=re.match(r'(\S+)\s+(\S+)\s+(\S+)\s+(\S+)\s+([\d.]+) Mrays/s \[.*\] err (\d+) brute (\d+)/',line)
        if m:
            runs[(w,n)][(m[1],m[2],m[3],m[4])]=float(m[5])
            if m[3]!='embree': errs[w]+=int(m[6])+int(m[7])
def q(v):
    v=sorted(v); n=len(v)
    def p(x):
        k=(n-1)*x; i=int(k); return v[i]+(v[min(i+1,n-1)]-v[i])*(k-i)
    return v[0],p(.25),statistics.median(v),p(.75),v[-1]
cells=collections.defaultdict(lambda: collections.defaultdict(list))
for (w,n),data in runs.items():
    keys=set((k[0],k[1]) for k in data)
    for cell,kind in keys:
        emb=max(data.get((cell,kind,'embree',c),0) for c in ['1','8','16','1M'])
        sah=data.get((cell,kind,'bvh-sah','best'),0); lb=data.get((cell,kind,'lbvh','best'),0)
        cells[(kind,'arbor')][ (cell,w) ].append(max(sah,lb)/emb)
        cells[(kind,'bvh-sah')][(cell,w)].append(sah/emb)
        cells[(kind,'lbvh')][(cell,w)].append(lb/emb)
print('runs',sorted(runs.keys()),'errors vs scalar+brute (arbor configs):',dict(errs))
percell={}
for (kind,st),m in sorted(cells.items()):
    out=[]
    for w in 'AB':
        vals={c:statistics.median(v) for (c,ww),v in m.items() if ww==w}
        percell[(kind,st,w)]=vals
        if vals:
            mn,q1,md,q3,mx=q(list(vals.values())); worst=min(vals,key=vals.get)
            out.append(f"{w}: {mn:.2f} / {q1:.2f} / **{md:.2f}** / {q3:.2f} / {mx:.2f} ({worst})")
    print(f"| {kind} | {st} | {len(vals)} | "+' | '.join(out)+' |')
if len(sys.argv)>2:
    kind=sys.argv[2]
    a=percell[(kind,'arbor','A')]; b=percell[(kind,'arbor','B')]
    for c in sorted(a): print(f"| {c} | {a[c]:.2f} | {b.get(c,0):.2f} | {b.get(c,0)/a[c]:.2f} |")
