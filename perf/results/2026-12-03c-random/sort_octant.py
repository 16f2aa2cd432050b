import sys, struct
src, dst = sys.argv[1], sys.argv[2]
b = open(src,'rb').read()
hdr = b[:16]; recs = [b[16+32*i:16+32*(i+1)] for i in range((len(b)-16)//32)]
def octant(rec):
    dx,dy,dz = struct.unpack_from('<3f', rec, 16)
    import math
    return int(math.copysign(1,dx)<0) | int(math.copysign(1,dy)<0)<<1 | int(math.copysign(1,dz)<0)<<2
out = []
for s in range(0, len(recs), 1024):
    blk = recs[s:s+1024]
    out += sorted(blk, key=octant)  # stable
open(dst,'wb').write(hdr + b''.join(out))
