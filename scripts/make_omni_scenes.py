#!/usr/bin/env python3
"""Writes the omnicam paper's two built-in scenes, scenes/maze.toml and scenes/factory.toml, in the
spirit of the paper's USARSim worlds (docs/omnicam.md), and scenes/factory_smoke.toml, the same drive
through the factory filling with smoke. Run from the repository root."""

HEADER = "# Written by scripts/make_omni_scenes.py; edit the script, not this file.\n"


def box(name, material, cx, cy, sx, sy, z0, z1):
    return (f'[[surfaces]]\nname = "{name}"\nmaterial = "{material}"\ntype = "box"\n'
            f'position = [{cx:g}, {cy:g}, {(z0 + z1) / 2:g}]\nsize = [{sx:g}, {sy:g}, {z1 - z0:g}]\n\n')


def hedge_x(name, y, x0, x1, t, h, mat):  # a wall along x at y
    return box(name, mat, (x0 + x1) / 2, y, x1 - x0 + t, t, 0, h)


def hedge_y(name, x, y0, y1, t, h, mat):  # a wall along y at x
    return box(name, mat, x, (y0 + y1) / 2, t, y1 - y0 + t, 0, h)


def robot(keys):
    s = '[[robots]]\nname = "p2dx"\n'
    for t, x, y, yaw in keys:
        s += f'[[robots.keyframes]]\ntime_s = {t:g}\nposition = [{x:g}, {y:g}, 0]\nyaw_deg = {yaw:g}\n'
    return s + "\n"


RIG = '''# The robot: a Sick LMS200 at 0.3 m facing forward and, above it on the same vertical axis, the
# omnicam's viewpoint at 0.931 m (the paper's OmniP2DX: h = 0.931 m, 1024x768, R = 192 px).
[[sensors]]
name = "sick"
type = "lms200"
robot = "p2dx"
position = [0, 0, 0.3]
rpy_deg = [0, 0, -90]

[[cameras]]
name = "omni"
kind = "omni"
robot = "p2dx"
position = [0, 0, 0.931]
width = 1024
height = 768
mirror_radius_px = 192
base_radius_px = 40

'''

SUN = '''[[lights]]
name = "sky"
kind = "ambient"
radiance = 0.25

[[lights]]
name = "sun"
kind = "directional"
rpy_deg = [0, 70, 30]
irradiance = 3.0

'''

# The hall's lamps: light from straight above (no hard shadows at the walls' feet) and the hall's
# weak bounce light. (Lit by an even sky alone, the floor at a wall's foot is darker than the floor
# the histogram learns, and the omnicam read 0.19 m short on average: docs/omnicam.md.)
ROOF = '''[[lights]]
name = "lamps"
kind = "directional"
rpy_deg = [0, 90, 0]
irradiance = 3.0

[[lights]]
name = "bounce"
kind = "ambient"
radiance = 0.1

'''


def maze():
    s = HEADER + '''# The omnicam paper's maze: narrow corridors between hedges on grass, the hedge nearly the floor's
# colour, many turns; the robot starts in the middle of the top corridor and drives to the exit.
# Axes: x east, y north, z up; metres, seconds.

[scene]
name = "maze"
description = "hedge maze on grass (the omnicam paper's maze), a robot driving through it"
t_start_s = 0
t_end_s = 60

[[materials]]
name = "grass"
albedo = [0.10, 0.30, 0.06]
nir_785 = 0.4
nir_905 = 0.4

[[materials]]
name = "hedge"
albedo = [0.07, 0.21, 0.05]
nir_785 = 0.5
nir_905 = 0.5

[[surfaces]]
name = "ground"
material = "grass"
type = "quad"
corner = [-8, -8, 0]
u = [16, 0, 0]
v = [0, 16, 0]

'''
    t, h, m = 0.3, 1.2, "hedge"
    s += hedge_x("hedge_north", 0.75, -4.5, 4.5, t, h, m)
    s += hedge_x("hedge_a", -0.75, -4.5, 3.0, t, h, m)
    s += hedge_x("hedge_b", -2.25, -3.0, 4.5, t, h, m)
    s += hedge_x("hedge_south", -3.75, -4.5, 3.0, t, h, m)  # the exit: east end of the bottom corridor
    s += hedge_y("hedge_east", 4.5, -2.25, 0.75, t, h, m)
    s += hedge_y("hedge_west", -4.5, -3.75, 0.75, t, h, m)
    s += robot([(0, -2, 0, 0), (12, 3.75, 0, 0), (15, 3.75, 0, -90), (17, 3.75, -1.5, -90), (20, 3.75, -1.5, 180),
                (36, -3.75, -1.5, 180), (39, -3.75, -1.5, -90), (41, -3.75, -3.0, -90), (44, -3.75, -3.0, 0),
                (60, 5.5, -3.0, 0)])
    return s + RIG + SUN


def factory(smoke=False):
    s = HEADER + '''# The omnicam paper's factory: wide corridors around a partition, few turns, distinct objects — a
# cabinet on legs that the laser (0.3 m up) sees through and the camera sees, a tank, machines; lamps
# overhead; the robot drives a loop round the partition.
# Axes: x east, y north, z up; metres, seconds.

[scene]
name = "factory"
description = "factory hall with wide corridors (the omnicam paper's factory), a robot driving a loop"
t_start_s = 0
t_end_s = 48

[[materials]]
name = "concrete"
albedo = [0.36, 0.35, 0.33]
nir_785 = 0.45
nir_905 = 0.45

[[materials]]
name = "wall_paint"
albedo = [0.55, 0.60, 0.70]
nir_785 = 0.7
nir_905 = 0.7

[[materials]]
name = "cabinet_orange"
albedo = [0.70, 0.30, 0.05]
nir_785 = 0.6
nir_905 = 0.6

[[materials]]
name = "machine_yellow"
albedo = [0.75, 0.62, 0.08]
nir_785 = 0.6
nir_905 = 0.6

[[materials]]
name = "tank_steel"
albedo = [0.25, 0.26, 0.30]
nir_785 = 0.5
nir_905 = 0.5
specular = 0.3
roughness = 0.3

[[surfaces]]
name = "floor"
material = "concrete"
type = "quad"
corner = [-7, -5, 0]
u = [14, 0, 0]
v = [0, 10, 0]

'''
    t, h, m = 0.2, 2.5, "wall_paint"
    s += hedge_x("wall_north", 4.0, -6.0, 6.0, t, h, m)
    s += hedge_x("wall_south", -4.0, -6.0, 6.0, t, h, m)
    s += hedge_y("wall_east", 6.0, -4.0, 4.0, t, h, m)
    s += hedge_y("wall_west", -6.0, -4.0, 4.0, t, h, m)
    s += hedge_x("partition", 0.0, -2.5, 2.5, 0.4, 1.8, m)
    # The cabinet: a body from 0.5 m to 1.8 m on four legs (the laser at 0.3 m sees the legs only).
    s += box("cabinet_body", "cabinet_orange", 0.0, 3.55, 1.2, 0.5, 0.5, 1.8)
    for i, (dx, dy) in enumerate([(-0.55, -0.2), (0.55, -0.2), (-0.55, 0.2), (0.55, 0.2)]):
        s += box(f"cabinet_leg_{i}", "cabinet_orange", dx, 3.55 + dy, 0.05, 0.05, 0, 0.5)
    s += box("machine", "machine_yellow", 3.5, -3.3, 1.2, 0.9, 0, 1.2)
    s += '[[surfaces]]\nname = "tank"\nmaterial = "tank_steel"\ntype = "cylinder"\nposition = [-5.2, 3.2, 0.0]\nradius = 0.5\nheight = 2.0\n\n'
    s += robot([(0, -4.0, 2.0, 0), (16, 4.0, 2.0, 0), (19, 4.0, 2.0, -90), (24, 4.0, -2.0, -90), (27, 4.0, -2.0, 180),
                (43, -4.0, -2.0, 180), (46, -4.0, -2.0, 90), (48, -4.0, 0.0, 90)])
    if not smoke:
        return s + RIG + ROOF
    return s + RIG.replace('rpy_deg = [0, 0, -90]\n', 'rpy_deg = [0, 0, -90]\nmodel = "physical"\n') + ROOF + SMOKE


# The smoke drive (experiments/omnicam_smoke): the same hall, robot and path, filling with a thin
# haze (the smoke machine of the smoke paper's Bocas scene, well mixed) and a denser plume from
# beside the machine drifting west along the south corridor. A URG-04LX rides above the Sick; both
# lasers use the physical return model, so each fails as its receiver does.
SMOKE = '''[[sensors]]
name = "urg"
type = "urg04lx"
robot = "p2dx"
position = [0, 0, 0.4]
rpy_deg = [0, 0, 0]
model = "physical"

[[smoke]]
name = "haze"
type = "box"
min = [-6.1, -4.1, 0.0]
max = [6.1, 4.1, 2.5]
voxel = 0.25
medium = "theatrical_fog"
timeline = { kind = "machine", on = [[4.0, 48.0]], fill_per_s = 0.00001, dissolve_s = 600.0 }

[[smoke]]
name = "fire"
type = "plume"
source = [2.6, -2.6, 0.4]
rate_per_s = 3.0
lifetime_s = 20.0
rise_m_s = 0.0
wind_m_s = [-0.15, 0.05, 0.0]
spread_m_s = 0.08
radius_m = 0.3
growth_m_s = 0.02
peak_density = 0.01
start_s = 6.0
stop_s = 40.0
voxel = 0.2
medium = { name = "plume_smoke", lidar_ratio_sr = 40.0 }
seed = 7
'''


if __name__ == "__main__":
    open("scenes/maze.toml", "w").write(maze())
    open("scenes/factory.toml", "w").write(factory())
    open("scenes/factory_smoke.toml", "w").write(factory(smoke=True).replace(
        'name = "factory"\ndescription = "factory hall with wide corridors (the omnicam paper\'s factory), a robot driving a loop"',
        'name = "factory_smoke"\ndescription = "the factory drive, the hall filling with smoke (haze and a plume)"'))
