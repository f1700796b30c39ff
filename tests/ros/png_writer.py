"""A minimal PNG encoder on Python's zlib, for the ROS test writers' compressed topics (independent of the
OpenCV and libpng that depthcloud decodes with)."""
import struct
import zlib


def png(width, height, bit_depth, colour_type, rows):
    """A PNG of unfiltered `rows` (each row's samples; 16-bit ones big-endian), colour type 0 gray or 2 RGB."""
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    header = struct.pack(">IIBBBBB", width, height, bit_depth, colour_type, 0, 0, 0)
    pixels = zlib.compress(b"".join(b"\0" + row for row in rows))
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", pixels) + chunk(b"IEND", b"")
