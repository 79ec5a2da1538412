"""An independent writer of ROS 1 bags for tests/test_bag.cpp: Debian's python3-rosbag and
python3-sensor-msgs write /front/scan LaserScans and /tf beside them, the values following the
rule tests/js/write_bag.mjs uses: scan k at stamp 10 + 0.5 k s, beam i reads 0.5 + 0.001 (i + k) m,
beam 3 +Inf and beam 5 NaN in every scan. With FRAMES, /cam/image Images too, drawn by
tests/js/write_bag.mjs's rule (bgra8, rows padded to 40 bytes, 8×6 px at stamp 10 + 0.5 k s, grey
but for the block x 2…5, y 1…3 of (R, G, B) = (200, 200 − 20 k, 200 − 40 k): saturation 0.2 k),
recorded 1 ms after their stamps. With FIRST_S, the scans start at FIRST_S s instead of 10 s (0: a
message at ROS 1's "no time", which librosbag drops from its index).
Usage: python3 write_ros1_bag.py FILE.bag none|bz2|lz4 SCANS BEAMS [FRAMES [FIRST_S]]"""
import math
import sys

import genpy
import rosbag
from geometry_msgs.msg import TransformStamped
from sensor_msgs.msg import Image, LaserScan
from tf2_msgs.msg import TFMessage

path, compression, scans, beams = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
frames = int(sys.argv[5]) if len(sys.argv) > 5 else 0
first_ns = round(float(sys.argv[6]) * 1e9) if len(sys.argv) > 6 else 10_000_000_000
with rosbag.Bag(path, "w", compression=compression, chunk_threshold=16 * 1024) as bag:
    for k in range(scans):
        ns = first_ns + k * 500_000_000
        stamp = genpy.Time(ns // 10**9, ns % 10**9)
        s = LaserScan()
        s.header.stamp, s.header.frame_id, s.header.seq = stamp, "laser", k
        s.angle_min, s.angle_max = -2.0862138271331787, 2.0923497676849365
        s.angle_increment, s.scan_time, s.range_min, s.range_max = 0.006135923322290182, 0.1, 0.02, 5.6
        ranges = [0.5 + 0.001 * (i + k) for i in range(beams)]
        ranges[3], ranges[5] = math.inf, math.nan
        s.ranges = ranges
        bag.write("/front/scan", s, stamp)
        t = TransformStamped()
        t.header.stamp, t.header.frame_id, t.child_frame_id = stamp, "map", "base_link"
        t.transform.translation.x, t.transform.rotation.w = k, 1.0
        bag.write("/tf", TFMessage(transforms=[t]), stamp)
    for k in range(frames):
        ns = 10_000_000_000 + k * 500_000_000
        img = Image()
        img.header.stamp, img.header.frame_id, img.header.seq = genpy.Time(ns // 10**9, ns % 10**9), "cam", k
        img.height, img.width, img.encoding, img.is_bigendian, img.step = 6, 8, "bgra8", 0, 40
        data = bytearray([7] * (40 * 6))
        for y in range(6):
            for x in range(8):
                inside = 2 <= x < 6 and 1 <= y < 4
                r, g, b = (200, 200 - 20 * k, 200 - 40 * k) if inside else (128, 128, 128)
                data[y * 40 + 4 * x : y * 40 + 4 * x + 4] = bytes([b, g, r, 255])
        img.data = bytes(data)
        recorded = ns + 1_000_000
        bag.write("/cam/image", img, genpy.Time(recorded // 10**9, recorded % 10**9))
