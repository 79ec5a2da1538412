// An independent writer of the bags smokescan reads (tests/test_bag.cpp): Foxglove's @mcap/core
// writes an MCAP file (zstd chunks by @foxglove/wasm-zstd, small enough that there are several)
// whose LaserScans @foxglove/rosmsg2-serialization serialises, with a /tf topic beside them.
// Log and publish times are 1 ms after each header stamp (a reader must take the stamp).
// The values follow a rule the test knows: scan k at stamp 10 + 0.5 k s, beam i reads
// 0.5 + 0.001 (i + k) m, beam 3 +Inf and beam 5 NaN in every scan.
// With FRAMES, an Image topic /cam/image too (bgra8, rows padded to 40 bytes): frame k, 8×6 px at
// stamp 10 + 0.5 k s, grey (128) but for the block x 2…5, y 1…3, which is (R, G, B) =
// (200, 200 − 20 k, 200 − 40 k): HSV saturation 0.2 k.
// With CLOUDS, a PointCloud2 topic /ouster/points too, laid out as Ouster's ROS 2 driver lays out
// its points (48 bytes: x y z float32 at 0, 4, 8, intensity float32 at 16, t uint32 [ns] at 20,
// reflectivity uint16 at 24, ring uint16 at 26, ambient uint16 at 28, range uint32 [mm] at 32),
// organised 2 rows × 3 points with each row padded to 160 bytes (row_step): cloud k at stamp
// 10 + 0.1 k s, point (r, c) at x = k + 0.25 c, y = r, z = −0.5, intensity 10 k + c, t 1000 (c + 1)
// ns, ring r; point (1, 2) has NaN x, y, z (no return).
// Usage: node write_bag.mjs FILE.mcap SCANS BEAMS [FRAMES [CLOUDS]]
import { open } from "node:fs/promises";
import { McapWriter } from "@mcap/core";
import { parse } from "@foxglove/rosmsg";
import { MessageWriter } from "@foxglove/rosmsg2-serialization";
import zstd from "@foxglove/wasm-zstd";

const [file, scansArg, beamsArg, framesArg, cloudsArg] = process.argv.slice(2);
const scans = Number(scansArg), beams = Number(beamsArg), frames = Number(framesArg ?? 0), clouds = Number(cloudsArg ?? 0);
await zstd.isLoaded;
const handle = await open(file, "w");
let position = 0n;
const writable = {
  write: async (buffer) => {
    await handle.write(buffer);
    position += BigInt(buffer.byteLength);
  },
  position: () => position,
};
const writer = new McapWriter({
  writable,
  chunkSize: 4096,
  compressChunk: (data) => ({ compression: "zstd", compressedData: zstd.compress(data, 3) }),
});
await writer.start({ profile: "ros2", library: "independent test writer" });
const header = "MSG: std_msgs/Header\nbuiltin_interfaces/Time stamp\nstring frame_id\n";
const time = "MSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec\n";
const sep = "=".repeat(80) + "\n";
const scanDef =
  "std_msgs/Header header\nfloat32 angle_min\nfloat32 angle_max\nfloat32 angle_increment\n" +
  "float32 time_increment\nfloat32 scan_time\nfloat32 range_min\nfloat32 range_max\n" +
  "float32[] ranges\nfloat32[] intensities\n" + sep + header + sep + time;
const tfDef =
  "geometry_msgs/TransformStamped[] transforms\n" + sep + "MSG: geometry_msgs/TransformStamped\n" +
  "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/Transform transform\n" + sep +
  "MSG: geometry_msgs/Transform\ngeometry_msgs/Vector3 translation\ngeometry_msgs/Quaternion rotation\n" + sep +
  "MSG: geometry_msgs/Vector3\nfloat64 x\nfloat64 y\nfloat64 z\n" + sep +
  "MSG: geometry_msgs/Quaternion\nfloat64 x\nfloat64 y\nfloat64 z\nfloat64 w\n" + sep + header + sep + time;
const enc = new TextEncoder();
const scanSchema = await writer.registerSchema({ name: "sensor_msgs/msg/LaserScan", encoding: "ros2msg", data: enc.encode(scanDef) });
const tfSchema = await writer.registerSchema({ name: "tf2_msgs/msg/TFMessage", encoding: "ros2msg", data: enc.encode(tfDef) });
const scanChannel = await writer.registerChannel({ schemaId: scanSchema, topic: "/front/scan", messageEncoding: "cdr", metadata: new Map() });
const tfChannel = await writer.registerChannel({ schemaId: tfSchema, topic: "/tf", messageEncoding: "cdr", metadata: new Map() });
const scanWriter = new MessageWriter(parse(scanDef, { ros2: true }));
const tfWriter = new MessageWriter(parse(tfDef, { ros2: true }));
for (let k = 0; k < scans; k++) {
  const ns = 10_000_000_000n + BigInt(k) * 500_000_000n;
  const stamp = { sec: Number(ns / 1_000_000_000n), nanosec: Number(ns % 1_000_000_000n) };
  const ranges = new Float32Array(beams);
  for (let i = 0; i < beams; i++) ranges[i] = 0.5 + 0.001 * (i + k);
  ranges[3] = Infinity;
  ranges[5] = NaN;
  const scan = {
    header: { stamp, frame_id: "laser" },
    angle_min: -2.0862138271331787, angle_max: 2.0923497676849365, angle_increment: 0.006135923322290182,
    time_increment: 0, scan_time: 0.1, range_min: 0.02, range_max: 5.6, ranges, intensities: new Float32Array(0),
  };
  await writer.addMessage({ channelId: scanChannel, sequence: k, logTime: ns + 1_000_000n, publishTime: ns + 1_000_000n, data: scanWriter.writeMessage(scan) });
  const tf = { transforms: [{ header: { stamp, frame_id: "map" }, child_frame_id: "base_link",
    transform: { translation: { x: k, y: 0, z: 0 }, rotation: { x: 0, y: 0, z: 0, w: 1 } } }] };
  await writer.addMessage({ channelId: tfChannel, sequence: k, logTime: ns + 1_000_000n, publishTime: ns + 1_000_000n, data: tfWriter.writeMessage(tf) });
}
const imageDef =
  "std_msgs/Header header\nuint32 height\nuint32 width\nstring encoding\nuint8 is_bigendian\nuint32 step\n" +
  "uint8[] data\n" + sep + header + sep + time;
if (frames > 0) {
  const imageSchema = await writer.registerSchema({ name: "sensor_msgs/msg/Image", encoding: "ros2msg", data: enc.encode(imageDef) });
  const imageChannel = await writer.registerChannel({ schemaId: imageSchema, topic: "/cam/image", messageEncoding: "cdr", metadata: new Map() });
  const imageWriter = new MessageWriter(parse(imageDef, { ros2: true }));
  const width = 8, height = 6, step = 40;
  for (let k = 0; k < frames; k++) {
    const ns = 10_000_000_000n + BigInt(k) * 500_000_000n;
    const stamp = { sec: Number(ns / 1_000_000_000n), nanosec: Number(ns % 1_000_000_000n) };
    const data = new Uint8Array(step * height).fill(7);  // the padding: never read
    for (let y = 0; y < height; y++)
      for (let x = 0; x < width; x++) {
        const inside = x >= 2 && x < 6 && y >= 1 && y < 4;
        const [r, g, b] = inside ? [200, 200 - 20 * k, 200 - 40 * k] : [128, 128, 128];
        data.set([b, g, r, 255], y * step + 4 * x);
      }
    const image = { header: { stamp, frame_id: "cam" }, height, width, encoding: "bgra8", is_bigendian: 0, step, data };
    await writer.addMessage({ channelId: imageChannel, sequence: k, logTime: ns + 1_000_000n, publishTime: ns + 1_000_000n, data: imageWriter.writeMessage(image) });
  }
}
const cloudDef =
  "std_msgs/Header header\nuint32 height\nuint32 width\nsensor_msgs/PointField[] fields\nbool is_bigendian\n" +
  "uint32 point_step\nuint32 row_step\nuint8[] data\nbool is_dense\n" + sep + header + sep + time + sep +
  "MSG: sensor_msgs/PointField\nuint8 INT8=1\nuint8 UINT8=2\nuint8 INT16=3\nuint8 UINT16=4\nuint8 INT32=5\n" +
  "uint8 UINT32=6\nuint8 FLOAT32=7\nuint8 FLOAT64=8\nstring name\nuint32 offset\nuint8 datatype\nuint32 count\n";
if (clouds > 0) {
  const cloudSchema = await writer.registerSchema({ name: "sensor_msgs/msg/PointCloud2", encoding: "ros2msg", data: enc.encode(cloudDef) });
  const cloudChannel = await writer.registerChannel({ schemaId: cloudSchema, topic: "/ouster/points", messageEncoding: "cdr", metadata: new Map() });
  const cloudWriter = new MessageWriter(parse(cloudDef, { ros2: true }));
  const F32 = 7, U32 = 6, U16 = 4;
  const fields = [
    { name: "x", offset: 0, datatype: F32, count: 1 }, { name: "y", offset: 4, datatype: F32, count: 1 },
    { name: "z", offset: 8, datatype: F32, count: 1 }, { name: "intensity", offset: 16, datatype: F32, count: 1 },
    { name: "t", offset: 20, datatype: U32, count: 1 }, { name: "reflectivity", offset: 24, datatype: U16, count: 1 },
    { name: "ring", offset: 26, datatype: U16, count: 1 }, { name: "ambient", offset: 28, datatype: U16, count: 1 },
    { name: "range", offset: 32, datatype: U32, count: 1 },
  ];
  const height = 2, width = 3, pointStep = 48, rowStep = 160;
  for (let k = 0; k < clouds; k++) {
    const ns = 10_000_000_000n + BigInt(k) * 100_000_000n;
    const stamp = { sec: Number(ns / 1_000_000_000n), nanosec: Number(ns % 1_000_000_000n) };
    const data = new Uint8Array(rowStep * height).fill(0xAB);  // padding: never read
    const view = new DataView(data.buffer);
    for (let r = 0; r < height; r++)
      for (let c = 0; c < width; c++) {
        const at = r * rowStep + c * pointStep, none = r === 1 && c === 2;
        view.setFloat32(at + 0, none ? NaN : k + 0.25 * c, true);
        view.setFloat32(at + 4, none ? NaN : r, true);
        view.setFloat32(at + 8, none ? NaN : -0.5, true);
        view.setFloat32(at + 16, 10 * k + c, true);
        view.setUint32(at + 20, 1000 * (c + 1), true);
        view.setUint16(at + 24, 77, true);
        view.setUint16(at + 26, r, true);
        view.setUint16(at + 28, 5, true);
        view.setUint32(at + 32, 1234, true);
      }
    const cloud = { header: { stamp, frame_id: "os_lidar" }, height, width, fields, is_bigendian: false,
      point_step: pointStep, row_step: rowStep, data, is_dense: false };
    await writer.addMessage({ channelId: cloudChannel, sequence: k, logTime: ns + 1_000_000n, publishTime: ns + 1_000_000n, data: cloudWriter.writeMessage(cloud) });
  }
}
await writer.end();
await handle.close();
