#!/usr/bin/env python3
"""Corrupted PNG normal images through `pointshade normalmap`, corrupted EXRs through `compare`
and `merge`.
   Usage: tools/mutations/images.py SEED COUNT
"""
import random, subprocess, os, sys, shutil
from common import SHARED, ROOT, WORK, POINTSHADE as P, verdict
random.seed(int(sys.argv[1]))
P=os.path.join(ROOT,'target/release/pointshade')
d=WORK
png=open(os.path.join(SHARED,'normalmaps/normal.png'),'rb').read()
# small exrs
subprocess.run([P,'render',os.path.join(ROOT,'scenes/lambert.toml'),'-o',d+'/a.exr','--width','32','--height','24','--quiet'],check=True)
subprocess.run([P,'render',os.path.join(ROOT,'scenes/lambert.toml'),'-o',d+'/c0.exr','--width','32','--height','24','--crop','0,0,16,24','--quiet'],check=True)
subprocess.run([P,'render',os.path.join(ROOT,'scenes/lambert.toml'),'-o',d+'/c1.exr','--width','32','--height','24','--crop','16,0,32,24','--quiet'],check=True)
exr=open(d+'/a.exr','rb').read(); c0=open(d+'/c0.exr','rb').read(); c1=open(d+'/c1.exr','rb').read()
def mut(b):
    b=bytearray(b)
    r=random.random()
    if r<0.3: return bytes(b[:random.randrange(len(b))])
    for _ in range(random.randint(1,40)):
        i=random.randrange(len(b)); b[i]=random.randrange(256)
    return bytes(b)
bad=0
for it in range(int(sys.argv[2])):
    kind=random.choice(['normalmap','compare','merge'])
    if kind=='normalmap':
        open(d+'/n.png','wb').write(mut(png) if random.random()<0.9 else png[:random.randrange(100)])
        cmd=[P,'normalmap',d+'/n.png','--brdf',random.choice(['lambert','blinn-phong','cook-torrance']),'--preset',random.choice(['tp','physical']),'-o',d+'/o.png','--quiet']
    elif kind=='compare':
        open(d+'/m.exr','wb').write(mut(exr))
        cmd=[P,'compare',d+'/m.exr',d+'/a.exr']
    else:
        open(d+'/m0.exr','wb').write(mut(c0))
        cmd=[P,'merge',d+'/m0.exr',d+'/c1.exr','-o',d+'/mm.exr']
    problem=verdict(cmd[1:])
    if problem:
        bad+=1; k=f'{d}/bad{sys.argv[1]}-{it}'; os.makedirs(k,exist_ok=True)
        for f in ['n.png','m.exr','m0.exr']:
            if os.path.exists(d+'/'+f): shutil.copy(d+'/'+f,k)
        print('BAD',kind,k,problem)
print('done, bad', bad)
