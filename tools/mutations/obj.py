#!/usr/bin/env python3
"""Mutated OBJ and MTL files (meshes/ of this repository) through `pointshade render`.
   Usage: tools/mutations/obj.py SEED COUNT
"""
import random, os, sys, shutil
from common import SHARED, ROOT, WORK, POINTSHADE as P, verdict
random.seed(int(sys.argv[1]))
P=os.path.join(ROOT,'target/release/pointshade')
srcs=[os.path.join(ROOT,'meshes/cornell-box.obj'),os.path.join(ROOT,'meshes/icosphere-no-normals.obj'),os.path.join(ROOT,'meshes/uv-sphere-coarse.obj'),os.path.join(ROOT,'meshes/plane.obj')]
mtl=open(os.path.join(ROOT,'meshes/cornell-box.mtl')).read().splitlines()+['newmtl pbr','Kd 0.5 0.5 0.5','Pr 0.3','Pm 1','newmtl shiny','Kd 0.2 0.2 0.2','Ks 0.5 0.5 0.5','Ns 50']
toks=['nan','inf','-1','0','1e39','-1e39','3e38','99999999','-99999','1/1/1','0/0','//','x','','1e-45','2147483648','4294967297']
d=WORK
scene='[camera]\nposition = [0.0, 0.5, 4.0]\nlook_at = [0.0, 0.0, 0.0]\nfov = 40.0\n[film]\nwidth = 24\nheight = 16\n[[light]]\ntype = "point"\nposition = [1.0, 2.0, 3.0]\nintensity = 10.0\n[[object]]\nmesh = "m.obj"\n'
open(os.path.join(d,'s.toml'),'w').write(scene)
bad=0
for it in range(int(sys.argv[2])):
    src=random.choice(srcs)
    lines=open(src).read().splitlines()
    ml=list(mtl)
    if not any(l.startswith('mtllib') for l in lines): lines.insert(0,'mtllib m.mtl')
    lines=[('mtllib m.mtl' if l.startswith('mtllib') else l) for l in lines]
    if random.random()<0.5: lines.insert(2,'usemtl '+random.choice(['pbr','shiny','red','nosuch']))
    for _ in range(random.randint(1,4)):
        target=lines if random.random()<0.8 else ml
        i=random.randrange(len(target)); parts=target[i].split(' ')
        r=random.random()
        if r<0.6 and len(parts)>1:
            j=random.randrange(1,len(parts)); parts[j]=random.choice(toks); target[i]=' '.join(parts)
        elif r<0.75: del target[i]
        elif r<0.9: target.insert(i, target[i])
        else: target[i]=target[i][:random.randrange(len(target[i])+1)]
    open(os.path.join(d,'m.obj'),'w').write('\n'.join(lines)+'\n')
    open(os.path.join(d,'m.mtl'),'w').write('\n'.join(ml)+'\n')
    problem=verdict(['render',os.path.join(d,'s.toml'),'-o',os.path.join(d,'o.exr'),'--quiet'], 20)
    if problem:
        bad+=1; k=f'{d}/bad{sys.argv[1]}-{it}'; os.makedirs(k,exist_ok=True)
        for f in ['m.obj','m.mtl','s.toml']: shutil.copy(os.path.join(d,f),k)
        print('BAD',k,problem)
print('done, bad', bad)
