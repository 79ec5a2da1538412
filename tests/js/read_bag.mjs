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
    const text = new TextDecoder().decode(schema.data);
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
for (let r; (r = stream.nextRecord()); ) {
  if (r.type === "Message") streamed++;
  if (r.type === "Chunk") chunks++;
  if (r.type === "MessageIndex") messageIndexes++;
  if (r.type === "DataEnd") dataEndCrc = r.dataSectionCrc;
}
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
