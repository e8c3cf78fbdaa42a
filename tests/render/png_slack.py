#!/usr/bin/env python3
# png_slack.py A.png B.png PIXELS LEVELS: exit 0 when at most PIXELS pixels of the two same-sized
# 8-bit PNGs differ, none by more than LEVELS/255 in any channel; prints what differs. For
# define_exact.sh's SLACK (a lever exact in real arithmetic whose two programs the compiler may
# round differently). Plain Python: zlib and the PNG filters, no imaging library.
import zlib,struct,sys
def load(p):
    d=open(p,'rb').read(); i=8; w=h=0; idat=b''; ct=0
    while i<len(d):
        n=struct.unpack('>I',d[i:i+4])[0]; t=d[i+4:i+8]; c=d[i+8:i+8+n]; i+=12+n
        if t==b'IHDR': w,h,bd,ct=struct.unpack('>IIBB',c[:10])
        elif t==b'IDAT': idat+=c
    bpp={6:4,2:3}[ct]; raw=zlib.decompress(idat); s=w*bpp; out=[]; prev=bytearray(s); o=0
    for y in range(h):
        f=raw[o]; line=bytearray(raw[o+1:o+1+s]); o+=1+s
        for x in range(s):
            a=line[x-bpp] if x>=bpp else 0; b=prev[x]; cc=prev[x-bpp] if x>=bpp else 0
            if f==1: line[x]=(line[x]+a)&255
            elif f==2: line[x]=(line[x]+b)&255
            elif f==3: line[x]=(line[x]+(a+b)//2)&255
            elif f==4:
                pa=abs(b-cc); pb=abs(a-cc); pc=abs(a+b-2*cc)
                pr=a if pa<=pb and pa<=pc else (b if pb<=pc else cc); line[x]=(line[x]+pr)&255
        out.append(line); prev=line
    return w,h,bpp,out
w,h,bpp,A=load(sys.argv[1]); w2,h2,_,B=load(sys.argv[2])
if (w,h)!=(w2,h2): print(f"sizes differ: {w}x{h} against {w2}x{h2}"); sys.exit(1)
n=0;m=0
for y in range(h):
    for x in range(w):
        dm=max(abs(A[y][x*bpp+k]-B[y][x*bpp+k]) for k in range(3))
        if dm: n+=1; m=max(m,dm)
print(f"{n} of {w*h} pixels differ, by up to {m}/255")
sys.exit(0 if n<=int(sys.argv[3]) and m<=int(sys.argv[4]) else 1)
