// An independent reader of the MCAP files smokescan writes (tests/test_bag.cpp): Foxglove's
// @mcap/core reads the file twice — from its summary and indexes (McapIndexedReader: the footer,
// the summary CRC, chunk indexes, message indexes) and from start to end (McapStreamReader: every
// record, each chunk's CRC) — and @foxglove/rosmsg2-serialization decodes each message from the
// schema the file carries. The data section's CRC is computed here with @foxglove/crc.
// Prints one JSON object: the summary, and every message decoded, in log-time order.
// Usage: node read_bag.mjs FILE.mcap
import { readFile } from "node:fs/promises";
import { McapIndexedReader, McapStreamReader } from "@mcap/core";
import { parse } from "@foxglove/rosmsg";
import { MessageReader } from "@foxglove/rosmsg2-serialization";
import { crc32 } from "@foxglove/crc";
import zstd from "@foxglove/wasm-zstd";

const file = process.argv[2];
const bytes = new Uint8Array(await readFile(file));
await zstd.isLoaded;
const decompressHandlers = { zstd: (buf, size) => zstd.decompress(buf, Number(size)) };

// The messages smokescan writes are decoded with their definitions as ROS 2 publishes them
// (sensor_msgs, geometry_msgs, tf2_msgs .msg files, comments left out), not with the schema text
// the file carries: a schema that drifted from ROS with its encoder would be caught.
const sep = "=".repeat(80) + "\n";
const header = "MSG: std_msgs/Header\nbuiltin_interfaces/Time stamp\nstring frame_id\n" + sep +
  "MSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec\n";
const official = {
  "sensor_msgs/msg/LaserScan":
    "std_msgs/Header header\nfloat32 angle_min\nfloat32 angle_max\nfloat32 angle_increment\n" +
    "float32 time_increment\nfloat32 scan_time\nfloat32 range_min\nfloat32 range_max\n" +
    "float32[] ranges\nfloat32[] intensities\n" + sep + header,
  "tf2_msgs/msg/TFMessage":
    "geometry_msgs/TransformStamped[] transforms\n" + sep + "MSG: geometry_msgs/TransformStamped\n" +
    "std_msgs/Header header\nstring child_frame_id\nTransform transform\n" + sep +
    "MSG: geometry_msgs/Transform\nVector3 translation\nQuaternion rotation\n" + sep +
    "MSG: geometry_msgs/Vector3\nfloat64 x\nfloat64 y\nfloat64 z\n" + sep +
    "MSG: geometry_msgs/Quaternion\nfloat64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n" + sep + header,
  "sensor_msgs/msg/PointCloud2":
    "std_msgs/Header header\nuint32 height\nuint32 width\nPointField[] fields\nbool is_bigendian\n" +
    "uint32 point_step\nuint32 row_step\nuint8[] data\nbool is_dense\n" + sep +
    "MSG: sensor_msgs/PointField\nuint8 INT8    = 1\nuint8 UINT8   = 2\nuint8 INT16   = 3\nuint8 UINT16  = 4\n" +
    "uint8 INT32   = 5\nuint8 UINT32  = 6\nuint8 FLOAT32 = 7\nuint8 FLOAT64 = 8\nstring name\nuint32 offset\n" +
    "uint8  datatype\nuint32 count\n" + sep + header,
  "sensor_msgs/msg/MultiEchoLaserScan":
    "std_msgs/Header header\nfloat32 angle_min\nfloat32 angle_max\nfloat32 angle_increment\n" +
    "float32 time_increment\nfloat32 scan_time\nfloat32 range_min\nfloat32 range_max\n" +
    "LaserEcho[] ranges\nLaserEcho[] intensities\n" + sep + "MSG: sensor_msgs/LaserEcho\nfloat32[] echoes\n" + sep +
    header,
  "sensor_msgs/msg/Image":
    "std_msgs/Header header\nuint32 height\nuint32 width\nstring encoding\nuint8 is_bigendian\nuint32 step\n" +
    "uint8[] data\n" + sep + header,
};
const problems = [];

// 1. Indexed.
const readable = {
  size: async () => BigInt(bytes.length),
  read: async (offset, size) => bytes.subarray(Number(offset), Number(offset + size)),
};
const indexed = await McapIndexedReader.Initialize({ readable, decompressHandlers });
const readers = new Map();
const decoded = [];
for await (const m of indexed.readMessages({ validateCrcs: true })) {
  const channel = indexed.channelsById.get(m.channelId);
  const schema = indexed.schemasById.get(channel.schemaId);
  if (!readers.has(schema.id)) {
    const text = official[schema.name] ?? new TextDecoder().decode(schema.data);
    readers.set(schema.id, new MessageReader(parse(text, { ros2: true })));
  }
  const reader = readers.get(schema.id);
  const message = reader.readMessage(m.data);
  if (reader.lastReadHadTrailingBytes()) throw new Error(`message ${m.sequence} on ${channel.topic}: trailing bytes`);
  decoded.push({
    topic: channel.topic,
    schema: schema.name,
    schemaEncoding: schema.encoding,
    messageEncoding: channel.messageEncoding,
    sequence: m.sequence,
    logTime: m.logTime,
    publishTime: m.publishTime,
    message,
  });
}

// 2. Streamed, every record, chunk CRCs checked; the Data End's CRC against the bytes before it.
const stream = new McapStreamReader({ decompressHandlers, validateCrcs: true, includeChunks: true });
stream.append(bytes);
let streamed = 0, dataEndCrc, chunks = 0, messageIndexes = 0;
const chunkRecords = [];
for (let r; (r = stream.nextRecord()); ) {
  if (r.type === "Message") streamed++;
  if (r.type === "Chunk") {
    chunks++;
    chunkRecords.push(r);
    if (r.uncompressedCrc === 0) problems.push(`chunk ${chunks - 1} has no CRC`);
  }
  if (r.type === "MessageIndex") messageIndexes++;
  if (r.type === "DataEnd") dataEndCrc = r.dataSectionCrc;
}
// 3. The summary against what was read: statistics, chunk indexes, summary offsets, the CRCs.
const logTimes = decoded.map((m) => m.logTime);
const min = logTimes.reduce((a, b) => (b < a ? b : a), logTimes[0] ?? 0n);
const max = logTimes.reduce((a, b) => (b > a ? b : a), logTimes[0] ?? 0n);
const st = indexed.statistics;
if (st.chunkCount !== chunks) problems.push(`statistics: ${st.chunkCount} chunks, ${chunks} read`);
if (st.messageCount !== BigInt(streamed)) problems.push(`statistics: ${st.messageCount} messages, ${streamed} read`);
if (st.messageStartTime !== min || st.messageEndTime !== max) problems.push("statistics: wrong message times");
for (const [id, n] of st.channelMessageCounts) {
  const topic = indexed.channelsById.get(id).topic;
  const seen = decoded.filter((m) => m.topic === topic).length;
  if (BigInt(seen) !== n) problems.push(`statistics: ${n} messages on ${topic}, ${seen} read`);
}
if (indexed.footer.summaryCrc === 0) problems.push("the footer has no summary CRC");
if (indexed.chunkIndexes.length !== chunkRecords.length) problems.push("a chunk index per chunk");
indexed.chunkIndexes.forEach((ci, i) => {
  const c = chunkRecords[i];
  if (!c) return;
  if (ci.messageStartTime !== c.messageStartTime || ci.messageEndTime !== c.messageEndTime)
    problems.push(`chunk index ${i}: times differ from its chunk's`);
  if (ci.compressedSize !== BigInt(c.records.byteLength) || ci.uncompressedSize !== c.uncompressedSize)
    problems.push(`chunk index ${i}: sizes differ from its chunk's`);
  if (ci.compression !== c.compression) problems.push(`chunk index ${i}: compression differs`);
  const at = Number(ci.chunkStartOffset);
  if (bytes[at] !== 0x06) problems.push(`chunk index ${i}: no chunk at byte ${at}`);
  const len = Number(new DataView(bytes.buffer, bytes.byteOffset + at + 1, 8).getBigUint64(0, true));
  if (BigInt(9 + len) !== ci.chunkLength) problems.push(`chunk index ${i}: chunk_length ${ci.chunkLength}, record ${9 + len}`);
  for (const [channel, offset] of ci.messageIndexOffsets) {
    const o = Number(offset);
    if (bytes[o] !== 0x07) problems.push(`chunk index ${i}: no message index at byte ${o}`);
    else if (new DataView(bytes.buffer, bytes.byteOffset + o + 9, 2).getUint16(0, true) !== channel)
      problems.push(`chunk index ${i}: the message index at byte ${o} is not channel ${channel}'s`);
  }
});
for (const [opcode, so] of indexed.summaryOffsetsByOpcode) {
  let at = Number(so.groupStart);
  const end = at + Number(so.groupLength);
  while (at < end) {
    if (bytes[at] !== opcode) {
      problems.push(`summary offset 0x${opcode.toString(16)}: a record of opcode ${bytes[at]} at byte ${at}`);
      break;
    }
    at += 9 + Number(new DataView(bytes.buffer, bytes.byteOffset + at + 1, 8).getBigUint64(0, true));
  }
  if (at !== end) problems.push(`summary offset 0x${opcode.toString(16)}: its group does not end at its length`);
}
for (const op of [0x03, 0x04, 0x08, 0x0b])
  if (!indexed.summaryOffsetsByOpcode.has(op)) problems.push(`no summary offset for opcode 0x${op.toString(16)}`);
if (!stream.done()) throw new Error("the stream reader did not reach a complete file");
// The Data End record is the first record of opcode 0x0F after the last chunk's message indexes:
// its position is the summary's start less its own 13 bytes.
const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
const footerAt = bytes.length - 8 - 29;
const summaryStart = view.getBigUint64(footerAt + 9, true);
const dataEndAt = Number(summaryStart) - 13;
if (bytes[dataEndAt] !== 0x0f) throw new Error(`no Data End record before the summary (at ${dataEndAt})`);
const dataCrc = crc32(bytes.subarray(0, dataEndAt));

const stats = indexed.statistics;
const json = JSON.stringify(
  {
    profile: indexed.header.profile,
    library: indexed.header.library,
    messageCount: stats.messageCount,
    channelCount: stats.channelCount,
    schemaCount: stats.schemaCount,
    chunkCount: stats.chunkCount,
    chunkIndexes: indexed.chunkIndexes.length,
    chunks,
    messageIndexes,
    streamedMessages: streamed,
    problems,
    dataEndCrc,
    dataCrc,
    compression: [...new Set(indexed.chunkIndexes.map((c) => c.compression))],
    topics: Object.fromEntries([...indexed.channelsById.values()].map((c) => [c.topic, c.id])),
    messages: decoded,
  },
  (key, value) => {
    if (typeof value === "bigint") return value.toString();
    if (typeof value === "number" && !Number.isFinite(value)) return String(value);
    if (value instanceof Float32Array || value instanceof Float64Array)
      return Array.from(value, (v) => (Number.isFinite(v) ? v : String(v)));
    if (value instanceof Uint8Array) return Buffer.from(value).toString("base64");
    return value;
  },
);
process.stdout.write(json + "\n");
