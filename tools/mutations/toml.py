#!/usr/bin/env python3
"""Mutated scene files (values, dropped and doubled lines) of scenes/ through `pointshade render`;
the mutant is written beside its original (so that its relative paths resolve) and removed.
   Usage: tools/mutations/toml.py SEED COUNT
"""
import random, os, sys, re, glob, shutil
from common import SHARED, ROOT, WORK, POINTSHADE as P, verdict
random.seed(int(sys.argv[1]))
P=os.path.join(ROOT,'target/release/pointshade')
scenes=[s for s in glob.glob(os.path.join(ROOT,'scenes/*.toml'))+glob.glob(os.path.join(ROOT,'scenes/validation/*.toml'))]
weird=['nan','inf','-inf','-1','0','1e39','-1e39','4294967296','"x"','[]','[1,2]','[nan, 0, 0]','true','1e-45','65537','100000']
bad=0
for it in range(int(sys.argv[2])):
    src=random.choice(scenes)
    lines=open(src).read().splitlines()
    for _ in range(random.randint(1,3)):
        i=random.randrange(len(lines)); l=lines[i]
        r=random.random()
        if '=' in l and not l.strip().startswith('#') and r<0.7:
            k=l.split('=')[0]; lines[i]=k+'= '+random.choice(weird)
        elif r<0.85: del lines[i]
        else: lines.insert(i, lines[i])
    d=os.path.dirname(src); f=os.path.join(d,'_fuzz_case.toml')
    open(f,'w').write('\n'.join(lines)+'\n')
    problem=verdict(['render',f,'-o',os.path.join(WORK,'out.png'),'--quiet'], 30)
    if problem:
        bad+=1; keep=os.path.join(WORK,f'tbad{sys.argv[1]}-{it}.toml'); shutil.copy(f,keep); print('BAD',keep,src,problem)
    os.remove(f)
print('done, bad', bad)
