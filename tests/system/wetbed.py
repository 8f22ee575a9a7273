"""A scene for tests that save and load in separate yade processes (run_yade): 18 spheres of 0.5 mm
in two touching layers on a dry floor, film liquid at 10 Pa·s, implicit viscous forces, Δt = 1 µs.
Script text, so that each process builds it the same way; a test appends what it adds."""

BED = '''
import json, os, sys
from yade import O, utils
import viscbridge, viscbridge.liquid as liquid
R = 0.5e-3
O.bodies.append(utils.wall(0, axis=2))
liquid.make_dry(ids=[0])
for k in range(2):
    for j in range(3):
        for i in range(3):
            O.bodies.append(utils.sphere(((i + 0.5) * 2 * R, (j + 0.5) * 2 * R, R + k * 2 * R), R))
O.engines = viscbridge.engines(viscosity=10.0, liquidModel='film', integration='implicit')
O.dt = 1e-6
'''
