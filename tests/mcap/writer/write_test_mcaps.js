#!/usr/bin/env node
// Writes the MCAP files mcap_replay_test.cpp replays, with an independent writer: Foxglove's @mcap/core and
// @foxglove/cdr (pinned in package-lock.json, installed by scripts/setup.sh).
//
// Usage: node write_test_mcaps.js OUT_DIR. Pixel values, stamps and calibrations follow formulas the C++ test
// recomputes, so every frame is checked pixel for pixel without reference images. The layout is a ROS 2
// RealSense wrapper's: /camera/camera/{depth,color}/{image_rect_raw,image_raw,camera_info}.
"use strict";

const fs = require("fs");
const path = require("path");
const zlib = require("zlib");
const { McapWriter, TempBuffer } = require("@mcap/core");
const { CdrWriter, EncapsulationKind } = require("@foxglove/cdr");
const zstd = require("@foxglove/wasm-zstd");
const lz4 = require("lz4js");

const FRAMES = 5;
const DEPTH_W = 64, DEPTH_H = 48, COLOR_W = 80, COLOR_H = 60;
const START_NS = 1000n * 1000000000n;
const FRAME_NS = 33333333n;
const COLOR_OFFSET_NS = 2000000n; // colour is stamped 2 ms after its depth image
const LOG_DELAY_NS = 5000000n; // received 5 ms after the stamp: replay must use the stamp, not the log time

const depthUnits = (x, y, i) => x + 100 * y + 1000 * i;
const colorRgb = (x, y, i) => [(3 * x + i) % 256, (4 * y) % 256, (7 * i + x + y) % 256];

const DEPTH_INFO = {
  width: DEPTH_W, height: DEPTH_H, k: [50, 0, 32, 0, 51, 24, 0, 0, 1],
  model: "plumb_bob", d: [0.1, -0.2, 0.001, 0.002, 0.05],
};
const COLOR_INFO = {
  width: COLOR_W, height: COLOR_H, k: [60, 0, 40, 0, 61, 30, 0, 0, 1],
  model: "rational_polynomial", d: [0.1, -0.2, 0.001, 0.002, 0.05, 0.01, 0.02, 0.03],
};

function header(w, stampNs) {
  w.int32(Number(stampNs / 1000000000n));
  w.uint32(Number(stampNs % 1000000000n));
  w.string("camera_depth_optical_frame");
}

function imageMessage(kind, stampNs, encoding, width, height, step, data, bigEndianPixels) {
  const w = new CdrWriter({ kind });
  header(w, stampNs);
  w.uint32(height);
  w.uint32(width);
  w.string(encoding);
  w.uint8(bigEndianPixels ? 1 : 0);
  w.uint32(step);
  w.uint8Array(data, true);
  return w.data;
}

const infraredValue = (x, y, i) => (x * 7 + y * 3 + i) & 0xff;

// 16UC1 millimetres, or 32FC1 metres (the same depths).
function depthImage(kind, i, stampNs, bigEndianPixels, encoding) {
  const bytes = encoding === "32FC1" ? 4 : 2;
  const data = new Uint8Array(DEPTH_W * DEPTH_H * bytes);
  const view = new DataView(data.buffer);
  for (let y = 0; y < DEPTH_H; ++y)
    for (let x = 0; x < DEPTH_W; ++x) {
      const at = (y * DEPTH_W + x) * bytes;
      if (bytes === 4) view.setFloat32(at, depthUnits(x, y, i) / 1000, !bigEndianPixels);
      else view.setUint16(at, depthUnits(x, y, i), !bigEndianPixels);
    }
  return imageMessage(kind, stampNs, encoding, DEPTH_W, DEPTH_H, DEPTH_W * bytes, data, bigEndianPixels);
}

// The same colours in each byte order the wrappers publish.
const COLOR_LAYOUTS = {
  rgb8: (r, g, b) => [r, g, b], bgr8: (r, g, b) => [b, g, r],
  rgba8: (r, g, b) => [r, g, b, 255], bgra8: (r, g, b) => [b, g, r, 255],
};

function colorImage(kind, i, stampNs, encoding) {
  const layout = COLOR_LAYOUTS[encoding];
  const bytes = layout(0, 0, 0).length;
  const data = new Uint8Array(COLOR_W * COLOR_H * bytes);
  for (let y = 0; y < COLOR_H; ++y)
    for (let x = 0; x < COLOR_W; ++x)
      data.set(layout(...colorRgb(x, y, i)), (y * COLOR_W + x) * bytes);
  return imageMessage(kind, stampNs, encoding, COLOR_W, COLOR_H, COLOR_W * bytes, data, false);
}

function infraredImage(kind, i, stampNs) {
  const data = new Uint8Array(DEPTH_W * DEPTH_H);
  for (let y = 0; y < DEPTH_H; ++y)
    for (let x = 0; x < DEPTH_W; ++x)
      data[y * DEPTH_W + x] = infraredValue(x, y, i);
  return imageMessage(kind, stampNs, "mono8", DEPTH_W, DEPTH_H, DEPTH_W, data, false);
}

// A PNG written here with Node's zlib (the replay decodes it with libpng): colour type 0 (gray) or 2 (RGB),
// unfiltered rows; rowBytes(y) gives row y's samples, 16-bit ones big-endian as PNG stores them.
const CRC_TABLE = Array.from({ length: 256 }, (_, n) => {
  let c = n;
  for (let k = 0; k < 8; ++k) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
  return c >>> 0;
});
function crc32(bytes) {
  let c = 0xffffffff;
  for (const b of bytes) c = CRC_TABLE[(c ^ b) & 0xff] ^ (c >>> 8);
  return (c ^ 0xffffffff) >>> 0;
}
function pngChunk(type, data) {
  const out = Buffer.alloc(12 + data.length);
  out.writeUInt32BE(data.length, 0);
  out.write(type, 4, "ascii");
  Buffer.from(data).copy(out, 8);
  out.writeUInt32BE(crc32(out.subarray(4, 8 + data.length)), 8 + data.length);
  return out;
}
function png(width, height, bitDepth, colourType, rowBytes) {
  const ihdr = Buffer.alloc(13); // compression, filter and interlace methods 0
  ihdr.writeUInt32BE(width, 0);
  ihdr.writeUInt32BE(height, 4);
  ihdr[8] = bitDepth;
  ihdr[9] = colourType;
  const rows = Array.from({ length: height }, (_, y) => Buffer.concat([Buffer.from([0]), Buffer.from(rowBytes(y))]));
  return Buffer.concat([Buffer.from([137, 80, 78, 71, 13, 10, 26, 10]), pngChunk("IHDR", ihdr),
    pngChunk("IDAT", zlib.deflateSync(Buffer.concat(rows))), pngChunk("IEND", Buffer.alloc(0))]);
}

function compressedMessage(kind, stampNs, format, data) {
  const w = new CdrWriter({ kind });
  header(w, stampNs);
  w.string(format);
  w.uint8Array(data, true);
  return w.data;
}

// image_transport's compressedDepth of 16UC1: its 12-byte header (format 0 = PNG, then the two inverse-depth
// quantisation floats, unused for 16UC1), then a 16-bit gray PNG of the millimetres.
function compressedDepthImage(kind, i, stampNs) {
  const header = Buffer.alloc(12);
  const image = png(DEPTH_W, DEPTH_H, 16, 0, (y) => {
    const row = Buffer.alloc(DEPTH_W * 2);
    for (let x = 0; x < DEPTH_W; ++x) row.writeUInt16BE(depthUnits(x, y, i), 2 * x);
    return row;
  });
  return compressedMessage(kind, stampNs, "16UC1; compressedDepth png", Buffer.concat([header, image]));
}

// image_transport's compressed plugin with png_level set: an RGB PNG.
function compressedColorImage(kind, i, stampNs) {
  const image = png(COLOR_W, COLOR_H, 8, 2, (y) => {
    const row = [];
    for (let x = 0; x < COLOR_W; ++x) row.push(...colorRgb(x, y, i));
    return row;
  });
  return compressedMessage(kind, stampNs, "rgb8; png compressed rgb8", image);
}

function cameraInfo(kind, stampNs, info) {
  const w = new CdrWriter({ kind });
  header(w, stampNs);
  w.uint32(info.height);
  w.uint32(info.width);
  w.string(info.model);
  w.float64Array(info.d, true);
  w.float64Array(info.k, false);
  w.float64Array([1, 0, 0, 0, 1, 0, 0, 0, 1], false); // r
  w.float64Array([...info.k.slice(0, 3), 0, ...info.k.slice(3, 6), 0, ...info.k.slice(6), 0], false); // p
  w.uint32(0); // binning_x
  w.uint32(0); // binning_y
  for (let j = 0; j < 4; ++j) w.uint32(0); // roi: x_offset, y_offset, height, width
  w.uint8(0); // roi.do_rectify
  return w.data;
}

const SCHEMAS = {
  "sensor_msgs/msg/Image":
    "std_msgs/Header header\nuint32 height\nuint32 width\nstring encoding\nuint8 is_bigendian\nuint32 step\nuint8[] data\n",
  "sensor_msgs/msg/CameraInfo":
    "std_msgs/Header header\nuint32 height\nuint32 width\nstring distortion_model\nfloat64[] d\nfloat64[9] k\n" +
    "float64[9] r\nfloat64[12] p\nuint32 binning_x\nuint32 binning_y\nRegionOfInterest roi\n",
  "sensor_msgs/msg/CompressedImage": "std_msgs/Header header\nstring format\nuint8[] data\n",
};

const compressors = {
  zstd: (data) => ({ compression: "zstd", compressedData: zstd.compress(data, 3) }),
  lz4: (data) => ({ compression: "lz4", compressedData: lz4.compress(data) }),
  none: undefined,
};

const chunked = (compressChunk) => ({ compressChunk, chunkSize: 40000 }); // a few frames per chunk

const withoutSummary = {
  useStatistics: false, useSummaryOffsets: false, useChunkIndex: false, repeatSchemas: false,
  repeatChannels: false, useAttachmentIndex: false, useMetadataIndex: false,
};

// Writes one file; returns its bytes and, per depth frame, the file offset at which its message was added
// (with chunkSize 1 every message is its own chunk, so that offset is where the frame's chunk starts).
// `images` picks the encodings: 16UC1 + rgb8 unless it says otherwise, and an infra1 mono8 stream; with
// `compressed`, depth and colour are image_transport's compressedDepth and compressed (PNG) topics instead.
async function write(options, kind = EncapsulationKind.CDR_LE, bigEndianPixels = false, images = {}) {
  const { depthEncoding = "16UC1", colorEncoding = "rgb8", infrared = false, compressed = false } = images;
  const buffer = new TempBuffer();
  const writer = new McapWriter({ writable: buffer, ...options });
  await writer.start({ profile: "ros2", library: "depthcloud test writer" });
  const schema = {};
  for (const [name, text] of Object.entries(SCHEMAS))
    schema[name] = await writer.registerSchema({ name, encoding: "ros2msg", data: new TextEncoder().encode(text) });
  const channel = async (topic, type) =>
    writer.registerChannel({ topic, schemaId: schema[type], messageEncoding: "cdr", metadata: new Map() });
  const depth = compressed
    ? await channel("/camera/camera/depth/image_rect_raw/compressedDepth", "sensor_msgs/msg/CompressedImage")
    : await channel("/camera/camera/depth/image_rect_raw", "sensor_msgs/msg/Image");
  const depthInfo = await channel("/camera/camera/depth/camera_info", "sensor_msgs/msg/CameraInfo");
  const color = compressed
    ? await channel("/camera/camera/color/image_raw/compressed", "sensor_msgs/msg/CompressedImage")
    : await channel("/camera/camera/color/image_raw", "sensor_msgs/msg/Image");
  const colorInfo = await channel("/camera/camera/color/camera_info", "sensor_msgs/msg/CameraInfo");
  const infra = infrared ? await channel("/camera/camera/infra1/image_rect_raw", "sensor_msgs/msg/Image") : 0;
  const depthOffsets = [];
  let sequence = 0;
  const add = (channelId, stampNs, data) => writer.addMessage({
    channelId, sequence: sequence++, logTime: stampNs + LOG_DELAY_NS, publishTime: stampNs + LOG_DELAY_NS, data,
  });
  for (let i = 0; i < FRAMES; ++i) {
    const stampNs = START_NS + BigInt(i) * FRAME_NS;
    depthOffsets.push(Number(buffer.position()));
    await add(depth, stampNs, compressed ? compressedDepthImage(kind, i, stampNs)
      : depthImage(kind, i, stampNs, bigEndianPixels, depthEncoding));
    await add(depthInfo, stampNs, cameraInfo(kind, stampNs, DEPTH_INFO));
    const colorStampNs = stampNs + COLOR_OFFSET_NS;
    await add(color, colorStampNs, compressed ? compressedColorImage(kind, i, colorStampNs)
      : colorImage(kind, i, colorStampNs, colorEncoding));
    if (infrared) await add(infra, stampNs, infraredImage(kind, i, stampNs));
    await add(colorInfo, stampNs + COLOR_OFFSET_NS, cameraInfo(kind, stampNs, COLOR_INFO));
  }
  await writer.end();
  return { bytes: buffer.get(), depthOffsets };
}

function rosbag2Metadata(file) {
  return `rosbag2_bagfile_information:\n  version: 8\n  storage_identifier: mcap\n` +
    `  duration:\n    nanoseconds: ${Number(FRAME_NS) * (FRAMES - 1)}\n` +
    `  relative_file_paths:\n    - ${file}\n  message_count: ${FRAMES * 4}\n`;
}

async function main() {
  const out = process.argv[2];
  if (!out) throw new Error("usage: write_test_mcaps.js OUT_DIR");
  await zstd.isLoaded;
  fs.mkdirSync(path.join(out, "rosbag2"), { recursive: true });
  const save = (name, bytes) => fs.writeFileSync(path.join(out, name), bytes);
  const zstdFile = await write(chunked(compressors.zstd));
  save("zstd.mcap", zstdFile.bytes);
  save("lz4.mcap", (await write(chunked(compressors.lz4))).bytes);
  save("uncompressed-chunks.mcap", (await write(chunked(compressors.none))).bytes);
  save("unchunked.mcap", (await write({ useChunks: false })).bytes);
  save("no-summary.mcap", (await write({ ...chunked(compressors.zstd), ...withoutSummary })).bytes);
  save("no-message-index.mcap", (await write({ ...chunked(compressors.lz4), useMessageIndex: false })).bytes);
  save("big-endian.mcap", (await write(chunked(compressors.zstd), EncapsulationKind.CDR_BE, true)).bytes);
  for (const [name, images] of Object.entries({
    "float-bgr.mcap": { depthEncoding: "32FC1", colorEncoding: "bgr8" },
    "rgba-infrared.mcap": { colorEncoding: "rgba8", infrared: true },
    "bgra-big-endian.mcap": { depthEncoding: "32FC1", colorEncoding: "bgra8" },
    "compressed.mcap": { compressed: true },
  }))
    save(name, (await write(chunked(compressors.zstd), name.includes("big") ? EncapsulationKind.CDR_BE : EncapsulationKind.CDR_LE, name.includes("big"), images)).bytes);
  // One chunk per message, cut 20 bytes into the chunk of depth frame 3: frames 0-2 survive.
  const small = await write({ compressChunk: compressors.zstd, chunkSize: 1 });
  save("truncated.mcap", small.bytes.subarray(0, small.depthOffsets[3] + 20));
  save("rosbag2/rosbag2_0.mcap", zstdFile.bytes);
  fs.writeFileSync(path.join(out, "rosbag2", "metadata.yaml"), rosbag2Metadata("rosbag2_0.mcap"));
}

main().catch((e) => {
  console.error(`write_test_mcaps.js: ${e.stack || e}`);
  process.exit(1);
});
