/* loopwriter.c - feed the test pattern (test_pattern.h) into a v4l2loopback output device.
 * usage: loopwriter -d /dev/videoN [-f FOURCC] [-w W] [-h H] [-n frames] [-r fps]
 * Prints what S_FMT(OUTPUT) kept (stock v4l2loopback replaces unknown fourccs). */
#include "test_pattern.h"

#include <errno.h>
#include <fcntl.h>
#include <linux/videodev2.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <unistd.h>

int main(int argc, char **argv)
{
	const char *dev = "/dev/video0", *want = "Z16 ";
	unsigned w = 640, h = 480, n = 100000, fps = 30;
	int opt;
	while ((opt = getopt(argc, argv, "d:f:w:h:n:r:")) != -1) {
		switch (opt) {
		case 'd': dev = optarg; break;
		case 'f': want = optarg; break;
		case 'w': w = atoi(optarg); break;
		case 'h': h = atoi(optarg); break;
		case 'n': n = atoi(optarg); break;
		case 'r': fps = atoi(optarg); break;
		default: return 2;
		}
	}
	char wb[5] = "    ";
	memcpy(wb, want, strlen(want) > 4 ? 4 : strlen(want));
	int fd = open(dev, O_RDWR);
	if (fd < 0) { perror("open"); return 1; }
	struct v4l2_format f = {.type = V4L2_BUF_TYPE_VIDEO_OUTPUT};
	f.fmt.pix.width = w;
	f.fmt.pix.height = h;
	f.fmt.pix.pixelformat = v4l2_fourcc(wb[0], wb[1], wb[2], wb[3]);
	f.fmt.pix.field = V4L2_FIELD_NONE;
	f.fmt.pix.bytesperline = w * 2;
	f.fmt.pix.sizeimage = w * h * 2;
	if (ioctl(fd, VIDIOC_S_FMT, &f)) { perror("S_FMT(OUTPUT)"); return 1; }
	uint32_t got = f.fmt.pix.pixelformat;
	printf("writer: asked '%s' %ux%u, S_FMT(OUTPUT) gave '%c%c%c%c' %ux%u bpl=%u sizeimage=%u\n",
	       wb, w, h, got & 0xff, (got >> 8) & 0xff, (got >> 16) & 0xff, got >> 24,
	       f.fmt.pix.width, f.fmt.pix.height, f.fmt.pix.bytesperline, f.fmt.pix.sizeimage);
	fflush(stdout);
	size_t sz = f.fmt.pix.sizeimage;
	uint16_t *buf = calloc(1, sz);
	for (unsigned s = 0; s < n; s++) {
		dc_fill_pattern(buf, f.fmt.pix.width, f.fmt.pix.height, f.fmt.pix.bytesperline / 2, s, 0);
		ssize_t r = write(fd, buf, sz);
		if (r != (ssize_t)sz) { fprintf(stderr, "write %zd: %s\n", r, strerror(errno)); return 1; }
		usleep(1000000 / fps);
	}
	close(fd);
	return 0;
}
