# Writes tests/data/saved_scene.xml.gz and saved_scene.json: a small scene with every slot of the
# registry active (pitois, goldman, willett, contact damping), saved by this release, and where its
# bodies are 50 steps after loading.  tests/yade/test_saved_scenes.py loads it: a scene saved by a
# release must keep loading and running the same.  Regenerate only when a change of the saved
# format is intended:  ./yadew run tests/data/make_saved_scene.py
import json
import sys
import os

from yade import O, utils
import yade.wrapper as yw

import viscbridge

HERE = os.path.dirname(os.path.abspath(sys.argv[0]))  # yade -x: __file__ is yade's own
R = 0.5e-3
mat = O.materials.append(yw.FrictMat(young=1e7, poisson=0.3, density=2500, frictionAngle=0.5))
O.bodies.append(utils.wall(0, axis=2, sense=1, material=mat))
for i in range(4):
    for k in range(2):
        O.bodies.append(utils.sphere((2.001 * R * i, 0.3 * R * k, R * (1.001 + 2.1 * k)), R, material=mat))
for b in O.bodies:
    if b.dynamic:
        b.state.vel = (0.01 * (b.id % 3 - 1), 0, -0.02)
O.engines = viscbridge.engines(viscosity=2.0, normalModel='pitois', tangentialModel='goldman', capillaryModel='willett',
                               surfaceTension=0.05, en=0.7, formationDistance=0.05 * R)
O.dt = 1e-8
O.trackEnergy = True
O.run(300, True)
O.save(os.path.join(HERE, 'saved_scene.xml.gz'))
O.run(50, True)
after = {b.id: list(b.state.pos) + list(b.state.vel) for b in O.bodies}
with open(os.path.join(HERE, 'saved_scene.json'), 'w') as fh:
    json.dump(dict(steps=50, after=after, energy=dict(O.energy.items()),
                   models=sorted({(i.phys.normalModel, i.phys.tangentialModel, i.phys.capillaryModel) for i in O.interactions if i.isReal})),
              fh, indent=1)
print('saved; %d interactions' % len([i for i in O.interactions if i.isReal]))
