#!/usr/bin/python3
"""Writes a rosbag2 sqlite3 recording (metadata.yaml + .db3) for db3_replay_test.cpp, independently of
depthcloud's code: Python's sqlite3 module with Humble's rosbag2 schema, and messages serialised here as
little-endian XCDR1 by struct. Frames follow tests/ros/replay_test_pattern.h (the MCAP writer's formulas).

Usage: make_test_db3.py OUT_DIR [PARTS [compressed]]  (writes OUT_DIR/metadata.yaml and OUT_DIR/rosbag2_0.db3,
or the frames split over PARTS files rosbag2_0.db3, rosbag2_1.db3, ... as a recorder's size limit splits them;
"compressed" records image_transport's compressedDepth and compressed topics, PNG made by png_writer.py with zlib)
"""
import math
import os
import sqlite3
import struct
import sys

from png_writer import png

FRAMES = 5
DEPTH_W, DEPTH_H, COLOR_W, COLOR_H = 64, 48, 80, 60
START_NS, FRAME_NS = 1000 * 1000000000, 33333333
COLOR_OFFSET_NS = 2000000  # colour is stamped 2 ms after its depth image
LOG_DELAY_NS = 5000000  # received 5 ms after the stamp: replay must use the stamp


def depth_units(x, y, i):
    return x + 100 * y + 1000 * i


def color_rgb(x, y, i):
    return ((3 * x + i) % 256, (4 * y) % 256, (7 * i + x + y) % 256)


class Cdr:
    """Little-endian XCDR1: 4-byte encapsulation header, primitives aligned to their size after it."""

    def __init__(self):
        self.out = bytearray(b"\x00\x01\x00\x00")

    def put(self, fmt, value):
        size = struct.calcsize("<" + fmt)
        self.out += b"\x00" * ((size - (len(self.out) - 4) % size) % size)
        self.out += struct.pack("<" + fmt, value)

    def string(self, s):
        self.put("I", len(s) + 1)
        self.out += s.encode() + b"\x00"

    def header(self, stamp_ns, frame_id):
        self.put("i", stamp_ns // 1000000000)
        self.put("I", stamp_ns % 1000000000)
        self.string(frame_id)


DEPTH_FRAME, COLOR_FRAME = "camera_depth_optical_frame", "camera_color_optical_frame"


def image(stamp_ns, frame_id, encoding, width, height, step, data):
    w = Cdr()
    w.header(stamp_ns, frame_id)
    w.put("I", height)
    w.put("I", width)
    w.string(encoding)
    w.put("B", 0)
    w.put("I", step)
    w.put("I", len(data))
    w.out += data
    return bytes(w.out)


def camera_info(stamp_ns, frame_id, width, height, k, d):
    w = Cdr()
    w.header(stamp_ns, frame_id)
    w.put("I", height)
    w.put("I", width)
    w.string("plumb_bob")
    w.put("I", len(d))
    for v in d + k + [1, 0, 0, 0, 1, 0, 0, 0, 1] + k[:3] + [0] + k[3:6] + [0] + k[6:] + [0]:
        w.put("d", float(v))
    for _ in range(6):  # binning_x, binning_y, roi x_offset y_offset height width
        w.put("I", 0)
    w.put("B", 0)  # roi.do_rectify
    return bytes(w.out)


def pose(i):
    """Frame i's camera_link in odom: translation (0.1 i, 0.2, 0.3) m, turned 0.1 i rad about z."""
    half = 0.05 * i
    return (0.1 * i, 0.2, 0.3), (0.0, 0.0, math.sin(half), math.cos(half))


def tf_message(stamp_ns, parent, transforms):
    """A TFMessage of (child, (translation, quaternion xyzw)) in `parent`."""
    w = Cdr()
    w.put("I", len(transforms))
    for child, (t, q) in transforms:
        w.header(stamp_ns, parent)
        w.string(child)
        for v in t + q:
            w.put("d", v)
    return bytes(w.out)


def moving_tf(i, stamp_ns):
    """camera_link's pose, and another frame's that the replay must not take for it."""
    return tf_message(stamp_ns, "odom", [("base_link", ((5.0, 5.0, 5.0), (0.0, 0.0, 0.0, 1.0))),
                                         ("camera_link", pose(i))])


def static_tf(stamp_ns):
    """The optical frames on camera_link, 15 mm either side of it along y: colour = depth + (0, 0.03, 0)."""
    still = (0.0, 0.0, 0.0, 1.0)
    return tf_message(stamp_ns, "camera_link", [(DEPTH_FRAME, ((0.0, 0.015, 0.0), still)),
                                                (COLOR_FRAME, ((0.0, -0.015, 0.0), still))])


def compressed_image(stamp_ns, frame_id, fmt, data):
    w = Cdr()
    w.header(stamp_ns, frame_id)
    w.string(fmt)
    w.put("I", len(data))
    w.out += data
    return bytes(w.out)


def compressed_depth_image(i, stamp_ns):
    """compressedDepth's 12-byte header (PNG, quantisation unused for 16UC1), then a 16-bit gray PNG."""
    rows = [b"".join(struct.pack(">H", depth_units(x, y, i)) for x in range(DEPTH_W)) for y in range(DEPTH_H)]
    data = struct.pack("<iff", 0, 0.0, 0.0) + png(DEPTH_W, DEPTH_H, 16, 0, rows)
    return compressed_image(stamp_ns, DEPTH_FRAME, "16UC1; compressedDepth png", data)


def compressed_color_image(i, stamp_ns):
    rows = [bytes(c for x in range(COLOR_W) for c in color_rgb(x, y, i)) for y in range(COLOR_H)]
    return compressed_image(stamp_ns, COLOR_FRAME, "rgb8; png compressed rgb8", png(COLOR_W, COLOR_H, 8, 2, rows))


def depth_image(i, stamp_ns):
    data = b"".join(struct.pack("<H", depth_units(x, y, i)) for y in range(DEPTH_H) for x in range(DEPTH_W))
    return image(stamp_ns, DEPTH_FRAME, "16UC1", DEPTH_W, DEPTH_H, 2 * DEPTH_W, data)


def color_image(i, stamp_ns):
    data = bytes(c for y in range(COLOR_H) for x in range(COLOR_W) for c in color_rgb(x, y, i))
    return image(stamp_ns, COLOR_FRAME, "rgb8", COLOR_W, COLOR_H, 3 * COLOR_W, data)


DEPTH_K = [50, 0, 32, 0, 51, 24, 0, 0, 1]
COLOR_K = [60, 0, 40, 0, 61, 30, 0, 0, 1]
LENS = [0.1, -0.2, 0.001, 0.002, 0.05]  # plumb_bob k1 k2 p1 p2 k3
COMPRESSED = len(sys.argv) > 3 and sys.argv[3] == "compressed"
TOPICS = [  # id, name, type
    (1, "/camera/camera/depth/image_rect_raw/compressedDepth", "sensor_msgs/msg/CompressedImage") if COMPRESSED
    else (1, "/camera/camera/depth/image_rect_raw", "sensor_msgs/msg/Image"),
    (2, "/camera/camera/depth/camera_info", "sensor_msgs/msg/CameraInfo"),
    (3, "/camera/camera/color/image_raw/compressed", "sensor_msgs/msg/CompressedImage") if COMPRESSED
    else (3, "/camera/camera/color/image_raw", "sensor_msgs/msg/Image"),
    (4, "/camera/camera/color/camera_info", "sensor_msgs/msg/CameraInfo"),
    (5, "/tf", "tf2_msgs/msg/TFMessage"),
    (6, "/tf_static", "tf2_msgs/msg/TFMessage"),
]


SCHEMA = """
    CREATE TABLE schema(schema_version INTEGER PRIMARY KEY, ros_distro TEXT NOT NULL);
    CREATE TABLE metadata(id INTEGER PRIMARY KEY, metadata_version INTEGER NOT NULL,
                          metadata TEXT NOT NULL);
    CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,
                        serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);
    CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, timestamp INTEGER NOT NULL,
                          data BLOB NOT NULL);
    CREATE INDEX timestamp_idx ON messages (timestamp ASC);
    INSERT INTO schema VALUES (3, 'humble');
"""


def frame_rows(i, topic_id):
    depth_ns = START_NS + i * FRAME_NS
    color_ns = depth_ns + COLOR_OFFSET_NS
    # Colour rows first: the store must order by receive time, not by row.
    rows = [
        (topic_id[3], color_ns + LOG_DELAY_NS,
         (compressed_color_image if COMPRESSED else color_image)(i, color_ns)),
        (topic_id[4], color_ns + LOG_DELAY_NS,
         camera_info(color_ns, COLOR_FRAME, COLOR_W, COLOR_H, COLOR_K, LENS)),
        (topic_id[1], depth_ns + LOG_DELAY_NS, (compressed_depth_image if COMPRESSED else depth_image)(i, depth_ns)),
        (topic_id[2], depth_ns + LOG_DELAY_NS,
         camera_info(depth_ns, DEPTH_FRAME, DEPTH_W, DEPTH_H, DEPTH_K, LENS)),
        # Stamped 1 ms after the depth image, as a pose estimator's output would be.
        (topic_id[5], depth_ns + LOG_DELAY_NS, moving_tf(i, depth_ns + 1000000)),
    ]
    if i == 0:  # latched once, as the driver publishes it
        rows.append((topic_id[6], depth_ns, static_tf(depth_ns)))
    return rows


def write_file(path, frames, part):
    if os.path.exists(path):
        os.remove(path)
    db = sqlite3.connect(path)
    db.executescript(SCHEMA)
    # Each later file numbers the topics differently, as a recorder that met them in another order would.
    ids = {tid: (tid + part - 1) % len(TOPICS) + 1 for tid, _, _ in TOPICS}
    db.executemany("INSERT INTO topics VALUES (?, ?, ?, 'cdr', '')",
                   [(ids[tid], name, kind) for tid, name, kind in TOPICS])
    rows = [row for i in frames for row in frame_rows(i, ids)]
    db.executemany("INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ?, ?)", rows)
    db.commit()
    db.close()
    return len(rows)


def write(directory, parts):
    os.makedirs(directory, exist_ok=True)
    names = [f"rosbag2_{p}.db3" for p in range(parts)]
    count = 0
    for p, name in enumerate(names):
        frames = [i for i in range(FRAMES) if i * parts // FRAMES == p]
        count += write_file(os.path.join(directory, name), frames, p)
    with open(os.path.join(directory, "metadata.yaml"), "w") as f:
        f.write("rosbag2_bagfile_information:\n  version: 5\n  storage_identifier: sqlite3\n"
                "  relative_file_paths:\n" + "".join(f"    - {n}\n" for n in names) +
                f"  message_count: {count}\n")


if __name__ == "__main__":
    write(sys.argv[1], int(sys.argv[2]) if len(sys.argv) > 2 else 1)
