"""Reads a point cloud (PCD or PLY) with Open3D's tensor reader, independently of smokescan, and
prints each field's values: one line per field, `name v1 v2 ...` (floats as repr, exact)."""
import sys

import open3d as o3d

cloud = o3d.t.io.read_point_cloud(sys.argv[1])
for name in sorted(cloud.point):
    values = cloud.point[name].numpy().reshape(-1)
    print(name, " ".join(repr(float(v)) for v in values))
