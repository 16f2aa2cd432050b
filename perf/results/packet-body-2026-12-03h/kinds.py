# Per kind, structure, path: min / median / max over cells of the per-cell median B/A: python3 kinds.py TABLE.md (summarize.py's output)
import sys, re, statistics
rows = {}
worst = {}
for line in open(sys.argv[1]):
    m = re.match(r'\| (\S+) \| (\S+) \| (\S+) \| (\S+) \| [\d.]+ \| [\d.]+ \| ([\d. ]+) \| \*\*([\d.]+)\*\* \|', line)
    if not m: continue
    key = (m[2], m[3], m[4]); r = float(m[6])
    rows.setdefault(key, []).append((r, m[1]))
print('| kind | structure | path | cells | min | median | max | worst cell |')
print('|---|---|---|---:|---:|---:|---:|---|')
order = ['primary', 'shadow', 'diffuse', 'random']
for key in sorted(rows, key=lambda k: (order.index(k[0]), k[1], k[2])):
    v = rows[key]; rs = [x for x, _ in v]
    print(f'| {key[0]} | {key[1]} | {key[2]} | {len(v)} | {min(rs):.3f} | {statistics.median(rs):.3f} | {max(rs):.3f} | {min(v)[1]} |')
per_kind_path = {}
for (k, s, p), v in rows.items(): per_kind_path.setdefault((k, p), []).extend(x for x, _ in v)
print()
print('| kind | path | cells (both structures) | median | min |')
print('|---|---|---:|---:|---:|')
for (k, p) in sorted(per_kind_path, key=lambda kp: (order.index(kp[0]), kp[1])):
    v = per_kind_path[(k, p)]
    print(f'| {k} | {p} | {len(v)} | {statistics.median(v):.3f} | {min(v):.3f} |')
