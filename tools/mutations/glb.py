#!/usr/bin/env python3
"""Mutated binary glTF files (header, chunk lengths, JSON and binary bytes, truncation) from
../shared's assets through `pointshade render`.
   Usage: tools/mutations/glb.py SEED COUNT
"""
import random, os, sys, shutil, struct
from common import SHARED, ROOT, WORK, POINTSHADE as P, verdict
random.seed(int(sys.argv[1]))
P=os.path.join(ROOT,'target/release/pointshade')
srcs=[os.path.join(SHARED,'gltf/Box/glTF-Binary/Box.glb'),os.path.join(SHARED,'gltf/BoxTextured/glTF-Binary/BoxTextured.glb'),os.path.join(SHARED,'gltf/Duck/glTF-Binary/Duck.glb')]
d=WORK; bad=0
for it in range(int(sys.argv[2])):
    b=bytearray(open(random.choice(srcs),'rb').read())
    jl=struct.unpack('<I',b[12:16])[0]
    r=random.random()
    if r<0.25:  # header / chunk length fields
        for off in random.sample([4,8,12,16,20+jl,24+jl],random.randint(1,2)):
            if off+4<=len(b): b[off:off+4]=struct.pack('<I',random.choice([0,1,7,jl,len(b),len(b)+100,2**31,2**32-1,random.randrange(2**32)]))
    elif r<0.6:  # bytes in the binary chunk
        for _ in range(random.randint(1,50)):
            i=random.randrange(20+jl,len(b)); b[i]=random.randrange(256)
    elif r<0.8:  # bytes in the json
        for _ in range(random.randint(1,5)):
            i=random.randrange(20,20+jl); b[i]=random.choice(b'0123456789-.eE"{}[],: ')
    else:
        b=b[:random.randrange(len(b))]
    open(d+'/m.glb','wb').write(bytes(b))
    problem=verdict(['render',d+'/m.glb','-o',d+'/o.png','--width','24','--height','16','--spp','1','--quiet'], 30)
    if problem:
        bad+=1; shutil.copy(d+'/m.glb', f'{d}/bad{sys.argv[1]}-{it}.glb'); print('BAD',it,problem)
print('done, bad', bad)
