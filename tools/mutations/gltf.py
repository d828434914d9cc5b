#!/usr/bin/env python3
"""Mutated glTF files (JSON values, the .bin, images) from ../shared's assets through
`pointshade render`: each must render or fail with one error line, never panic or hang.
   Usage: tools/mutations/gltf.py SEED COUNT   (after cargo build --release)
"""
import json, random, shutil, os, sys, copy
from common import SHARED, ROOT, WORK, POINTSHADE as P, verdict
random.seed(int(sys.argv[1]) if len(sys.argv)>1 else 1)
P=os.path.join(ROOT,'target/release/pointshade')
srcs=[os.path.join(SHARED,'gltf/BoxTextured/glTF'),os.path.join(SHARED,'gltf/Box/glTF'),os.path.join(SHARED,'gltf/LightsPunctualLamp/glTF'),os.path.join(SHARED,'gltf/Cameras/glTF')]
def paths(o, pre=()):
    if isinstance(o, dict):
        for k,v in o.items():
            yield pre+(k,)
            yield from paths(v, pre+(k,))
    elif isinstance(o, list):
        for i,v in enumerate(o):
            yield pre+(i,)
            yield from paths(v, pre+(i,))
def get(o,p):
    for k in p: o=o[k]
    return o
weird=[-2147483648, 4294967295, 5126, 5123, 34962, 'MASK', 'BLEND', {'index': 7}, {'index': 0, 'texCoord': 9}, {'KHR_texture_transform': {'scale': [0, 0], 'rotation': 1e30}}, None, -1, 0, 1e39, -1e39, 2**31, 2**32+3, 1.5, "x", [], {}, [1e30,1e30,1e30], [0,0,0,0], -0.0, 99999, [float('nan')]]
bad=0
for it in range(int(sys.argv[2]) if len(sys.argv)>2 else 100):
    src=random.choice(srcs)
    gl=[f for f in os.listdir(src) if f.endswith('.gltf')][0]
    doc=json.load(open(os.path.join(src,gl)))
    d=os.path.join(WORK,'case'); shutil.rmtree(d, ignore_errors=True); shutil.copytree(src,d)
    ps=list(paths(doc))
    for _ in range(random.randint(1,3)):
        p=random.choice(ps)
        try:
            parent=get(doc,p[:-1]); 
            r=random.random()
            if r<0.2 and isinstance(parent,dict): del parent[p[-1]]
            else: parent[p[-1]]=copy.deepcopy(random.choice(weird))
        except Exception: pass
        ps=list(paths(doc))
    txt=json.dumps(doc).replace('NaN','1e999') if random.random()<0.5 else json.dumps(doc)
    open(os.path.join(d,gl),'w').write(txt)
    # sometimes corrupt the bin
    bins=[f for f in os.listdir(d) if f.endswith('.bin')]
    imgs=[f for f in os.listdir(d) if f.endswith('.png') or f.endswith('.jpg')]
    if imgs and random.random()<0.3:
        f=os.path.join(d,random.choice(imgs)); b=bytearray(open(f,'rb').read())
        if random.random()<0.5: b=b[:random.randint(0,len(b))]
        else:
            for _ in range(random.randint(1,30)):
                if b: b[random.randrange(len(b))]=random.randrange(256)
        open(f,'wb').write(bytes(b))
    if bins and random.random()<0.3:
        b=bytearray(open(os.path.join(d,bins[0]),'rb').read())
        if random.random()<0.5: b=b[:random.randint(0,len(b))]
        else:
            for _ in range(20): 
                if b: b[random.randrange(len(b))]=random.randrange(256)
        open(os.path.join(d,bins[0]),'wb').write(bytes(b))
    problem=verdict(['render',os.path.join(d,gl),'-o',os.path.join(WORK,'out.png'),'--width','32','--height','24','--spp','1','--quiet'], 20)
    if problem:
        bad+=1
        keep=os.path.join(WORK,f'bad{sys.argv[1]}-{it}'); shutil.copytree(d, keep)
        print('BAD', keep, problem)
print('done, bad', bad)
