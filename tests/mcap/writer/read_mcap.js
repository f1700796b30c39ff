#!/usr/bin/env node
// Reads an MCAP file as Foxglove's tools do and prints what it holds as JSON, for mcap_export_test.cpp to
// check depthcloud's MCAP export against readers that are not ours: @mcap/core's stream reader (every
// record, chunk CRCs validated) and indexed reader (summary, chunk and message indexes), and each message
// decoded through its own schema by @foxglove/rosmsg + @foxglove/rosmsg2-serialization (Foxglove's
// ros2msg parser and CDR reader). The data section's and summary's CRCs are checked with node's zlib.
//
// Usage: node read_mcap.js FILE.mcap [--no-data]. Prints {records, chunkCompressions, crcs, summary, schemas,
// channels, messages: {topic: [...]}}; image data as base64, or as its byte count with --no-data (a long
// recording's base64 outgrows the longest string V8 can make). Exits 1 with the reason on stderr when a
// reader fails.
"use strict";

const fs = require("fs");
const zlib = require("zlib");
const { McapIndexedReader, McapStreamReader } = require("@mcap/core");
const { parse } = require("@foxglove/rosmsg");
const { MessageReader } = require("@foxglove/rosmsg2-serialization");
const zstd = require("@foxglove/wasm-zstd");

const decompressHandlers = {
  zstd: (data, size) => zstd.decompress(data, Number(size)),
};

// Every record in file order, inner chunk records included, counted by type.
function streamRecords(bytes) {
  const reader = new McapStreamReader({ includeChunks: true, decompressHandlers, validateCrcs: true });
  reader.append(bytes);
  const records = {};
  const chunkCompressions = [];
  let dataEnd;
  for (let record; (record = reader.nextRecord()); ) {
    records[record.type] = (records[record.type] || 0) + 1;
    if (record.type === "Chunk") chunkCompressions.push(record.compression);
    if (record.type === "DataEnd") dataEnd = record;
  }
  if (!reader.done()) throw new Error("the stream reader stopped before the end of the file");
  return { records, chunkCompressions, dataEnd };
}

// The CRCs the file states, against zlib's over the bytes they cover.
function crcs(bytes, indexed, dataEnd) {
  const footerStart = bytes.length - 8 - (1 + 8 + 8 + 8 + 4);
  const summaryStart = Number(indexed.footer.summaryStart);
  return {
    dataSection: dataEnd.dataSectionCrc === zlib.crc32(bytes.subarray(0, Number(indexed.dataEndOffset))),
    dataSectionStated: dataEnd.dataSectionCrc !== 0,
    summary: indexed.footer.summaryCrc === zlib.crc32(bytes.subarray(summaryStart, footerStart + 1 + 8 + 16)),
  };
}

function readable(bytes) {
  return {
    size: async () => BigInt(bytes.length),
    read: async (offset, size) => bytes.subarray(Number(offset), Number(offset + size)),
  };
}

const withData = process.argv[3] !== "--no-data";

function decoded(message) {
  const out = {};
  for (const [key, value] of Object.entries(message)) {
    if (value instanceof Uint8Array) out[key] = withData ? Buffer.from(value).toString("base64") : value.length;
    else if (value instanceof Float64Array) out[key] = Array.from(value);
    else if (Array.isArray(value)) out[key] = value.map((v) => (typeof v === "object" ? decoded(v) : v));
    else if (value && typeof value === "object") out[key] = decoded(value);
    else out[key] = typeof value === "bigint" ? value.toString() : value;
  }
  return out;
}

async function main() {
  const file = process.argv[2];
  const bytes = new Uint8Array(fs.readFileSync(file));
  await zstd.isLoaded;
  const { records, chunkCompressions, dataEnd } = streamRecords(bytes);
  const indexed = await McapIndexedReader.Initialize({ readable: readable(bytes), decompressHandlers });
  const readers = new Map();
  for (const [id, schema] of indexed.schemasById) {
    if (schema.encoding !== "ros2msg") throw new Error(`schema ${schema.name} is ${schema.encoding}`);
    readers.set(id, new MessageReader(parse(new TextDecoder().decode(schema.data), { ros2: true })));
  }
  const messages = {};
  for await (const m of indexed.readMessages()) {
    const channel = indexed.channelsById.get(m.channelId);
    const message = decoded(readers.get(channel.schemaId).readMessage(m.data));
    (messages[channel.topic] ||= []).push({ logTime: m.logTime.toString(), publishTime: m.publishTime.toString(),
                                           sequence: m.sequence, message });
  }
  const stats = indexed.statistics;
  console.log(JSON.stringify({
    profile: indexed.header.profile,
    records,
    chunkCompressions,
    crcs: crcs(bytes, indexed, dataEnd),
    summary: {
      chunkIndexes: indexed.chunkIndexes.length,
      chunkIndexCompressions: indexed.chunkIndexes.map((c) => c.compression),
      summaryOffsets: indexed.summaryOffsetsByOpcode.size,
      statistics: stats && { messageCount: stats.messageCount.toString(), chunkCount: stats.chunkCount,
                             channelCount: stats.channelCount, schemaCount: stats.schemaCount },
    },
    schemas: [...indexed.schemasById.values()].map((s) => ({ id: s.id, name: s.name, encoding: s.encoding })),
    channels: [...indexed.channelsById.values()].map((c) => ({ id: c.id, topic: c.topic, schemaId: c.schemaId,
                                                               messageEncoding: c.messageEncoding })),
    messages,
  }));
}

main().catch((e) => {
  console.error(`read_mcap: ${e.message}`);
  process.exit(1);
});
