# B / A per cell and round of ab.sh's reports: python3 summarize.py OUTDIR
import sys, re, glob, statistics, os
d = sys.argv[1]
rx = re.compile(r'^(\S+)\s+(\S+)\s+(\S+)\s+(\S+)\s+([\d.]+) Mrays/s \[.*\] err (\d+) brute (\d+)/(\d+)')
def load(f):
    out = {}
    for line in open(f):
        m = rx.match(line)
        if m:
            out[(m[1], m[2], m[3], m[4])] = (float(m[5]), int(m[6]), int(m[7]))
    return out
rounds = sorted({int(re.search(r'-(\d+)\.md', f)[1]) for f in glob.glob(d + '/A-*.md')})
ratios, A, B, errs = {}, {}, {}, 0
for k in rounds:
    fa, fb = f'{d}/A-{k}.md', f'{d}/B-{k}.md'
    if not (os.path.exists(fa) and os.path.exists(fb)): continue
    a, b = load(fa), load(fb)
    for key in b:
        if key in a:
            ratios.setdefault(key, []).append(b[key][0] / a[key][0])
            A.setdefault(key, []).append(a[key][0]); B.setdefault(key, []).append(b[key][0])
            errs += b[key][1] + b[key][2] + a[key][1] + a[key][2]
paths = sys.argv[2].split(',') if len(sys.argv) > 2 else None
print(f'rounds {len(next(iter(ratios.values())))}, disagreements (scalar + brute sample, A and B): {errs}')
print('| scene | kind | structure | path | A Mrays/s | B Mrays/s | B/A per round | median B/A |')
print('|---|---|---|---|---:|---:|---|---:|')
for key in sorted(ratios, key=lambda k: (k[0], ['primary','shadow','diffuse','random'].index(k[1]), k[2], k[3])):
    if paths and key[3] not in paths: continue
    r = ratios[key]
    print(f'| {key[0]} | {key[1]} | {key[2]} | {key[3]} | {statistics.median(A[key]):.2f} | {statistics.median(B[key]):.2f} | ' + ' '.join(f'{x:.2f}' for x in r) + f' | **{statistics.median(r):.3f}** |')
