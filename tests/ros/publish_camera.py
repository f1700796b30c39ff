#!/usr/bin/python3
"""Publishes a depth camera on ROS 1 topics with rospy, for ros_live_test.cpp and the latency bench.

Depth (16UC1 in mm or 32FC1 in m), an rgb8 colour image and the depth camera_info, at a fixed rate, with
pixel values from formulas the C++ test recomputes from each image's stamp: frame i is stamped
START + i * PERIOD, so a received frame names its own index. Runs until killed (SIGTERM or SIGINT).
"""
import argparse
import math
import os
import struct
import sys

import numpy as np
import rospy
from geometry_msgs.msg import TransformStamped
from sensor_msgs.msg import CameraInfo, CompressedImage, Image
from std_msgs.msg import String
from tf2_msgs.msg import TFMessage

from png_writer import png

FX, FY, CX, CY = 50.5, 51.25, 31.5, 23.75  # at the test's 64x48; scaled with the size


def depth_units(w, h, i):
    y, x = np.mgrid[0:h, 0:w]
    return (x % 100 + 100 * (y % 50) + 1000 * (i % 50) + 1).astype("<u2")


def color_rgb(w, h, i):
    y, x = np.mgrid[0:h, 0:w]
    rgb = np.stack([(3 * x + i) % 256, (4 * y) % 256, (7 * i + x + y) % 256], axis=-1)
    return rgb.astype(np.uint8)


class Cached:
    """The pixels repeat (depth every 50 frames, colour every 256): each distinct image is made once."""

    def __init__(self, make, period):
        self.make, self.period, self.images = make, period, {}

    def __call__(self, i):
        key = i % self.period
        if key not in self.images:
            self.images[key] = self.make(key)
        return self.images[key]


def image(stamp, encoding, w, h, step, data):
    m = Image()
    m.header.stamp = stamp
    m.header.frame_id = "camera_depth_optical_frame"
    m.encoding, m.width, m.height, m.step, m.is_bigendian, m.data = encoding, w, h, step, 0, data
    return m


def depth_bytes(args, i):
    units = depth_units(args.width, args.height, i)
    if args.encoding == "32FC1":
        return (units.astype("<f4") * np.float32(0.001)).tobytes()
    return units.tobytes()


def compressed_image(stamp, fmt, data):
    m = CompressedImage()
    m.header.stamp = stamp
    m.header.frame_id = "camera_depth_optical_frame"
    m.format, m.data = fmt, data
    return m


def compressed_depth(args, i):
    """image_transport's compressedDepth of 16UC1: the 12-byte header, then a 16-bit gray PNG."""
    units = depth_units(args.width, args.height, i).astype(">u2")
    return struct.pack("<iff", 0, 0.0, 0.0) + png(args.width, args.height, 16, 0,
                                                  [row.tobytes() for row in units])


def compressed_color(args, i):
    rgb = color_rgb(args.color_width, args.color_height, i)
    return png(args.color_width, args.color_height, 8, 2, [row.tobytes() for row in rgb])


def depth_image(args, stamp, data):
    bytes_per_pixel = 4 if args.encoding == "32FC1" else 2
    return image(stamp, args.encoding, args.width, args.height, bytes_per_pixel * args.width, data)


def camera_info(args, stamp):
    m = CameraInfo()
    m.header.stamp = stamp
    m.width, m.height = args.width, args.height
    sx, sy = args.width / 64.0, args.height / 48.0
    m.K = [FX * sx, 0, CX * sx, 0, FY * sy, CY * sy, 0, 0, 1]
    m.distortion_model = "plumb_bob"
    m.D = [0.0] * 5
    return m


def transform(stamp, parent, child, xyz, xyzw):
    t = TransformStamped()
    t.header.stamp, t.header.frame_id, t.child_frame_id = stamp, parent, child
    t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = xyz
    r = t.transform.rotation
    r.x, r.y, r.z, r.w = xyzw
    return t


def publish_tf_static(root):
    """root -> camera_link, 1 m up, latched on /tf_static as robot_state_publisher does."""
    pub = rospy.Publisher("/tf_static", TFMessage, queue_size=1, latch=True)
    pub.publish(TFMessage([transform(rospy.Time(0), root, "camera_link", (0, 0, 1), (0, 0, 0, 1))]))
    return pub


def camera_tf(stamp, i):
    """camera_link -> the depth image's optical frame: turned 90 degrees about z, sliding 1 cm a frame."""
    quarter = math.sqrt(0.5)
    return TFMessage([transform(stamp, "camera_link", "camera_depth_optical_frame",
                                (0.01 * (i % 50), 0.5, -0.25), (0, 0, quarter, quarter))])


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--ns", default="/camera")
    p.add_argument("--encoding", default="16UC1")
    p.add_argument("--width", type=int, default=64)
    p.add_argument("--height", type=int, default=48)
    p.add_argument("--color-width", type=int, default=80)
    p.add_argument("--color-height", type=int, default=60)
    p.add_argument("--rate", type=float, default=30.0)
    p.add_argument("--start", type=float, default=1000.0, help="stamp of frame 0 (s); 0: the wall clock")
    p.add_argument("--color-skew-ms", type=float, default=0.0)
    p.add_argument("--jump-back-file", default="", help="once this file exists, stamps go 10 s back")
    p.add_argument("--depth-type", default="image", choices=["image", "string"])
    p.add_argument("--tf-root", default="", help="publish /tf_static and /tf from this frame to the camera")
    p.add_argument("--transport", default="raw", choices=["raw", "compressed"],
                   help="compressed: 16UC1 depth on .../compressedDepth and colour on .../compressed, both PNG")
    args = p.parse_args()
    compressed = args.transport == "compressed"

    rospy.init_node("depthcloud_test_camera", anonymous=True)
    if args.depth_type == "string":
        depth_pub = rospy.Publisher(args.ns + "/depth/image_rect_raw", String, queue_size=2)
    elif compressed:
        depth_pub = rospy.Publisher(args.ns + "/depth/image_rect_raw/compressedDepth", CompressedImage,
                                    queue_size=2)
    else:
        depth_pub = rospy.Publisher(args.ns + "/depth/image_rect_raw", Image, queue_size=2)
    if compressed:
        color_pub = rospy.Publisher(args.ns + "/color/image_raw/compressed", CompressedImage, queue_size=2)
    else:
        color_pub = rospy.Publisher(args.ns + "/color/image_raw", Image, queue_size=2)
    info_pub = rospy.Publisher(args.ns + "/depth/camera_info", CameraInfo, queue_size=2)
    if args.tf_root:
        static_pub = publish_tf_static(args.tf_root)  # kept: a latched topic lives as long as its publisher
        tf_pub = rospy.Publisher("/tf", TFMessage, queue_size=10)
    period_ns = int(round(1e9 / args.rate))
    if compressed:
        colors = Cached(lambda i: compressed_color(args, i), 256)
        depths = Cached(lambda i: compressed_depth(args, i), 50)
    else:
        colors = Cached(lambda i: color_rgb(args.color_width, args.color_height, i).tobytes(), 256)
        depths = Cached(lambda i: depth_bytes(args, i), 50)
    rate = rospy.Rate(args.rate)
    i = 0
    while not rospy.is_shutdown():
        color_data, depth_data = colors(i), depths(i)  # before the stamp: "publish" is the stamp
        if args.start > 0:
            stamp_ns = int(args.start * 1e9) + i * period_ns
            if args.jump_back_file and os.path.exists(args.jump_back_file):
                stamp_ns -= 10_000_000_000
        else:
            stamp_ns = rospy.Time.now().to_nsec()
        stamp = rospy.Time(nsecs=stamp_ns)
        if args.tf_root:  # before the images: a receiver finds the pose when the image comes
            tf_pub.publish(camera_tf(stamp, i))
        info_pub.publish(camera_info(args, stamp))
        color_stamp = rospy.Time(nsecs=stamp_ns + int(args.color_skew_ms * 1e6))
        if compressed:
            color_pub.publish(compressed_image(color_stamp, "rgb8; png compressed rgb8", color_data))
        else:
            color_pub.publish(image(color_stamp, "rgb8", args.color_width, args.color_height,
                                    3 * args.color_width, color_data))
        if args.depth_type == "string":
            depth_pub.publish(String(data="not an image"))
        elif compressed:
            depth_pub.publish(compressed_image(stamp, "16UC1; compressedDepth", depth_data))
        else:
            depth_pub.publish(depth_image(args, stamp, depth_data))
        i += 1
        try:
            rate.sleep()
        except rospy.ROSInterruptException:
            break
    return 0


if __name__ == "__main__":
    sys.exit(main())
