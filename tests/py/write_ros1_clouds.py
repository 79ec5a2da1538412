"""An independent writer of a ROS 1 bag of a lidar's frames for tests/test_bag_runs.cpp: reads a
`smokescan scan --points` folder itself (frames.csv, binary PCD files: its own parser, numpy) and
writes each frame as a sensor_msgs/PointCloud2 on /points with Debian's python3-rosbag, its header
stamped at the frame's start and the message recorded 1 ms later (as a recorder receives it), its
fields and values as the PCD holds them, in two rows (a point of NaN coordinates, a driver's
no-return, appended when the count is odd), each row padded by PAD bytes (row_step = width ·
point_step + PAD) as some drivers lay out their clouds. With `short-rows`, row_step is one byte
short of a row's points (a bad layout a reader must refuse); with `zero-stamp`, the first frame's
header stamp is 0 (ROS 1's "no time", as a driver that never set it leaves it).
Usage: python3 write_ros1_clouds.py FRAMES_DIR OUT.bag none|bz2|lz4 [PAD [short-rows|zero-stamp]]"""
import csv
import os
import sys

import genpy
import numpy as np
import rosbag
from sensor_msgs.msg import PointCloud2, PointField

folder, out, compression = sys.argv[1], sys.argv[2], sys.argv[3]
pad = int(sys.argv[4]) if len(sys.argv) > 4 else 0
short_rows = len(sys.argv) > 5 and sys.argv[5] == "short-rows"
zero_stamp = len(sys.argv) > 5 and sys.argv[5] == "zero-stamp"
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
            offset = 0
            for name, kind, size, count in fields:
                msg.fields.append(PointField(name=name, offset=offset, datatype=DATATYPE[(kind, size)],
                                             count=count))
                offset += size * count
            points = np.frombuffer(data, dtype=np.uint8).reshape(n, step)
            if n % 2:  # a no-return point (NaN x, y, z; the rest zero) evens the rows
                nan = np.zeros(step, dtype=np.uint8)
                for name, kind, size, count in fields:
                    if name in ("x", "y", "z"):
                        at = [f[0] for f in fields].index(name)
                        first = sum(f[2] * f[3] for f in fields[:at])
                        nan[first:first + size] = np.frombuffer(
                            np.array([np.nan], dtype="<f4" if size == 4 else "<f8").tobytes(), dtype=np.uint8)
                points = np.vstack([points, nan])
            width = len(points) // 2
            msg.height, msg.width = 2, width
            msg.is_bigendian, msg.point_step = False, step
            msg.row_step = step * width + pad - (1 if short_rows else 0)
            rows = [points[r * width:(r + 1) * width].tobytes() + bytes(msg.row_step - step * width)
                    for r in range(2)] if not short_rows else [points.tobytes()]
            msg.data = b"".join(rows)
            msg.is_dense = False
            recorded = ns + 1_000_000
            if zero_stamp and row["frame"] == "0":
                msg.header.stamp = genpy.Time(0, 0)
            bag.write("/points", msg, genpy.Time(recorded // 10**9, recorded % 10**9))
