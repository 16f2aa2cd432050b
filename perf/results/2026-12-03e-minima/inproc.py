# The shared-leaves pass off (L0) against on (L32) from one bench_paths run with --shared-leaves 0,32
# (its stdout lines), configurations timed round-robin in one process: python3 inproc.py OUT.txt
import sys, re
rx = re.compile(r'^(\S+)\s+(\S+)\s+(\S+)/L(\d+)\s+(\S+)\s+([\d.]+) Mrays/s \[\s*([\d.]+)-\s*([\d.]+)\] err (\d+) brute (\d+)/(\d+)')
rows = {}
errs = 0; n = 0
for f in sys.argv[1:]:
    for line in open(f):
        m = rx.match(line)
        if not m: continue
        key = (m[1], m[2], m[3], m[5]); rows.setdefault(key, {}).setdefault(m[4], []).append(float(m[6]))
        errs += int(m[9]) + int(m[10]); n += 1
print(f'configurations {n}, disagreements with the scalar path + brute sample: {errs}')
print('| scene | kind | structure | path | off (L0) Mrays/s | on (L32) Mrays/s | on / off |')
print('|---|---|---|---|---:|---:|---:|')
order = ['primary','shadow','diffuse','random']
for key in sorted(rows, key=lambda k: (k[0], order.index(k[1]), k[2], k[3])):
    r = rows[key]
    off = sorted(r['0'])[len(r['0'])//2]; on = sorted(r['32'])[len(r['32'])//2]
    print(f'| {key[0]} | {key[1]} | {key[2]} | {key[3]} | {off:.2f} | {on:.2f} | **{on/off:.3f}** |')
