#!/usr/bin/python3
"""Writes the small ROS bags that bag_replay_test.cpp replays, with Debian's python3-rosbag.

Usage: make_test_bags.py OUT_DIR. Pixel values follow formulas that the C++ test recomputes, so every
frame is checked pixel for pixel without storing reference images.
"""
import math
import struct
import sys

import rosbag
import rospy
from geometry_msgs.msg import Transform
from sensor_msgs.msg import CameraInfo, CompressedImage, Image
from std_msgs.msg import Float32, String

from png_writer import png

FRAMES = 5
DEPTH_W, DEPTH_H = 64, 48
COLOR_W, COLOR_H = 80, 60
FRAME_NS = 33_333_333
START_S = 1000


def stamp(i, offset_ns=0):
    return rospy.Time(START_S, i * FRAME_NS + offset_ns)


def depth_units(x, y, i):
    return x + 100 * y + 1000 * i


def color_rgb(x, y, i):
    return ((3 * x + i) % 256, (4 * y) % 256, (7 * i + x + y) % 256)


def image(t, encoding, w, h, step, data):
    m = Image()
    m.header.stamp = t
    m.header.frame_id = "camera"
    m.encoding, m.width, m.height, m.step, m.data = encoding, w, h, step, bytes(data)
    return m


def depth16(i, encoding):
    data = bytearray()
    for y in range(DEPTH_H):
        for x in range(DEPTH_W):
            data += struct.pack("<H", depth_units(x, y, i))
    return image(stamp(i), encoding, DEPTH_W, DEPTH_H, 2 * DEPTH_W, data)


def depth32(i):
    data = bytearray()
    for y in range(DEPTH_H):
        for x in range(DEPTH_W):
            data += struct.pack("<f", depth_units(x, y, i) * 0.001)
    return image(stamp(i), "32FC1", DEPTH_W, DEPTH_H, 4 * DEPTH_W, data)


def infrared_value(x, y, i, wide):
    v = (x * 7 + y * 3 + i) & 0xFF
    return v * 257 if wide else v


def infrared(i, wide):
    """The depth sensor's infrared: 8UC1 as most RealSense models record it, or Y16 as mono16 (the YUYV
    bag), stamped 2 ms after its depth."""
    data = bytearray()
    for y in range(DEPTH_H):
        for x in range(DEPTH_W):
            v = infrared_value(x, y, i, wide)
            data += struct.pack("<H", v) if wide else bytes((v,))
    encoding, step = ("mono16", 2 * DEPTH_W) if wide else ("8UC1", DEPTH_W)
    return image(stamp(i, 2_000_000), encoding, DEPTH_W, DEPTH_H, step, data)


def color(i, encoding):
    """Colour stamped 1 ms after its depth; rows padded by 4 bytes to exercise the step."""
    data = bytearray()
    bpp = {"rgb8": 3, "bgr8": 3, "rgba8": 4, "YUYV": 2}[encoding]
    for y in range(COLOR_H):
        for x in range(COLOR_W):
            r, g, b = color_rgb(x, y, i)
            if encoding == "rgb8":
                data += bytes((r, g, b))
            elif encoding == "bgr8":
                data += bytes((b, g, r))
            elif encoding == "rgba8":
                data += bytes((r, g, b, 255))
            else:  # YUYV: the bytes themselves are the test's pattern
                data += bytes((r, g))
        data += bytes(4)
    return image(stamp(i, 1_000_000), encoding, COLOR_W, COLOR_H, bpp * COLOR_W + 4, data)


def camera_info(w, h, fx, fy, cx, cy, model, d):
    m = CameraInfo()
    m.width, m.height = w, h
    m.K = [fx, 0, cx, 0, fy, cy, 0, 0, 1]
    m.distortion_model = model
    m.D = d
    return m


def transform(t, angle_z):
    m = Transform()
    m.translation.x, m.translation.y, m.translation.z = t
    m.rotation.z, m.rotation.w = math.sin(angle_z / 2), math.cos(angle_z / 2)
    return m


def realsense(path, color_encoding):
    """RealSense Viewer's layout (librealsense's ROS bag format 3); the YUYV one LZ4-compressed, as the
    Viewer's recorder compresses."""
    t0 = rospy.Time(START_S)
    compression = rosbag.Compression.LZ4 if color_encoding == "YUYV" else rosbag.Compression.NONE
    with rosbag.Bag(path, "w", compression=compression) as bag:
        s0, s1 = "/device_0/sensor_0", "/device_0/sensor_1"
        bag.write(s0 + "/option/Depth Units/value", Float32(0.0001), t0)
        bag.write(s0 + "/Depth_0/info/camera_info",
                  camera_info(DEPTH_W, DEPTH_H, 60, 61, 31.5, 23.5, "Brown Conrady", [0, 0, 0, 0, 0]), t0)
        bag.write(s1 + "/Color_0/info/camera_info",
                  camera_info(COLOR_W, COLOR_H, 70, 71, 40.25, 29.75, "Inverse Brown Conrady",
                              [0.1, -0.2, 0.001, 0.002, 0.03]), t0)
        bag.write(s0 + "/Depth_0/tf/0", transform((0, 0, 0), 0), t0)
        bag.write(s1 + "/Color_0/tf/0", transform((0.015, 0.001, -0.002), 0.1), t0)
        for i in range(FRAMES):
            bag.write(s0 + "/Depth_0/image/data", depth16(i, "mono16"), stamp(i))
            bag.write(s0 + "/Infrared_1/image/data", infrared(i, color_encoding == "YUYV"), stamp(i))
            bag.write(s1 + "/Color_0/image/data", color(i, color_encoding), stamp(i, 1_000_000))


def write_driver_camera_info(bag, t0):
    """A ROS camera driver's camera_info beside its depth and colour images."""
    bag.write("/camera/depth/camera_info",
              camera_info(DEPTH_W, DEPTH_H, 50, 52, 32, 24, "plumb_bob", [0.01, 0, 0, 0, 0]), t0)
    bag.write("/camera/color/camera_info",
              camera_info(COLOR_W, COLOR_H, 62.5, 65, 40, 30, "plumb_bob", [0, 0, 0, 0, 0]), t0)


def generic(path):
    """A ROS camera driver's layout, recorded with rosbag record: namespaces with camera_info beside."""
    t0 = rospy.Time(START_S)
    with rosbag.Bag(path, "w") as bag:
        write_driver_camera_info(bag, t0)
        bag.write("/status", String("running"), t0)
        for i in range(FRAMES):
            bag.write("/camera/depth/image_rect_raw", depth32(i), stamp(i))
            bag.write("/camera/aligned/image_raw", depth16(i, "16UC1"), stamp(i))
            bag.write("/camera/color/image_raw", color(i, "bgr8"), stamp(i, 1_000_000))
            bag.write("/camera/ir/image_raw",
                      image(stamp(i), "bayer_rggb8", 4, 4, 4, bytes(16)), stamp(i))


def compressed_image(t, fmt, data):
    m = CompressedImage()
    m.header.stamp = t
    m.header.frame_id = "camera"
    m.format, m.data = fmt, data
    return m


def compressed(path):
    """The generic layout recorded from image_transport's compressedDepth and compressed (PNG) topics, as
    ROS 1's transports spell their formats: millimetre depth behind the 12-byte compressedDepth header."""
    t0 = rospy.Time(START_S)
    with rosbag.Bag(path, "w") as bag:
        write_driver_camera_info(bag, t0)
        for i in range(FRAMES):
            rows = [b"".join(struct.pack(">H", depth_units(x, y, i)) for x in range(DEPTH_W))
                    for y in range(DEPTH_H)]
            depth = struct.pack("<iff", 0, 0.0, 0.0) + png(DEPTH_W, DEPTH_H, 16, 0, rows)
            bag.write("/camera/depth/image_rect_raw/compressedDepth",
                      compressed_image(stamp(i), "16UC1; compressedDepth", depth), stamp(i))
            rows = [bytes(c for x in range(COLOR_W) for c in color_rgb(x, y, i)) for y in range(COLOR_H)]
            bag.write("/camera/color/image_raw/compressed",
                      compressed_image(stamp(i, 1_000_000), "bgr8; png compressed bgr8",
                                       png(COLOR_W, COLOR_H, 8, 2, rows)), stamp(i, 1_000_000))


def no_images(path):
    with rosbag.Bag(path, "w") as bag:
        bag.write("/status", String("no camera here"), rospy.Time(START_S))


def clock_jumps_back(path):
    with rosbag.Bag(path, "w") as bag:
        for i, j in enumerate([0, 1, 3, 2, 4]):
            m = depth16(j, "16UC1")
            bag.write("/camera/depth/image_rect_raw", m, stamp(i))


def main():
    out = sys.argv[1]
    for encoding in ("rgb8", "bgr8", "rgba8", "YUYV"):
        realsense(f"{out}/realsense_{encoding}.bag", encoding)
    generic(f"{out}/generic.bag")
    compressed(f"{out}/compressed.bag")
    no_images(f"{out}/no_images.bag")
    clock_jumps_back(f"{out}/clock_jumps_back.bag")


if __name__ == "__main__":
    main()
