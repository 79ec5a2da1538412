"""An independent writer of a ROS 1 bag of a lidar's frames for tests/test_bag_runs.cpp: reads a
`smokescan scan --points` folder itself (frames.csv, binary PCD files: its own parser, numpy) and
writes each frame as a sensor_msgs/PointCloud2 on /points with Debian's python3-rosbag, stamped at
the frame's start, its fields and values as the PCD holds them, each row padded by PAD bytes
(row_step = width · point_step + PAD) as some drivers lay out their clouds.
Usage: python3 write_ros1_clouds.py FRAMES_DIR OUT.bag none|bz2|lz4 [PAD]"""
import csv
import os
import sys

import genpy
import numpy as np
import rosbag
from sensor_msgs.msg import PointCloud2, PointField

folder, out, compression = sys.argv[1], sys.argv[2], sys.argv[3]
pad = int(sys.argv[4]) if len(sys.argv) > 4 else 0
DATATYPE = {("I", 1): PointField.INT8, ("U", 1): PointField.UINT8, ("I", 2): PointField.INT16,
            ("U", 2): PointField.UINT16, ("I", 4): PointField.INT32, ("U", 4): PointField.UINT32,
            ("F", 4): PointField.FLOAT32, ("F", 8): PointField.FLOAT64}


def read_pcd(path):
    """The header's fields (name, type, size, count) and the points' bytes of a binary PCD."""
    with open(path, "rb") as f:
        raw = f.read()
    header, at = {}, 0
    while True:
        end = raw.index(b"\n", at)
        words = raw[at:end].decode().split()
        at = end + 1
        if not words or words[0].startswith("#"):
            continue
        header[words[0]] = words[1:]
        if words[0] == "DATA":
            break
    assert header["DATA"] == ["binary"], header["DATA"]
    names, types = header["FIELDS"], header["TYPE"]
    sizes = [int(s) for s in header["SIZE"]]
    counts = [int(c) for c in header.get("COUNT", ["1"] * len(names))]
    n = int(header["POINTS"][0])
    step = sum(s * c for s, c in zip(sizes, counts))
    return list(zip(names, types, sizes, counts)), step, raw[at:at + n * step], n


with rosbag.Bag(out, "w", compression=compression) as bag:
    with open(os.path.join(folder, "frames.csv")) as index:
        for row in csv.DictReader(index):
            fields, step, data, n = read_pcd(os.path.join(folder, row["file"]))
            msg = PointCloud2()
            ns = round(float(row["start_s"]) * 1e9)
            msg.header.stamp = genpy.Time(ns // 10**9, ns % 10**9)
            msg.header.frame_id = "lidar"
            msg.height, msg.width = 1, n
            offset = 0
            for name, kind, size, count in fields:
                msg.fields.append(PointField(name=name, offset=offset, datatype=DATATYPE[(kind, size)],
                                             count=count))
                offset += size * count
            msg.is_bigendian, msg.point_step, msg.row_step = False, step, step * n + pad
            rows = np.frombuffer(data, dtype=np.uint8)
            msg.data = (rows.tobytes() + bytes(pad)) if n else bytes(pad)
            msg.is_dense = True
            bag.write("/points", msg, msg.header.stamp)
