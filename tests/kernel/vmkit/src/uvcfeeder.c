/* uvcfeeder.c - minimal userspace side of the Linux UVC gadget (f_uvc, kernel 6.1), for tests/kernel.
 * Adapted from ../shared/vmkit: frames carry the test pattern of test_pattern.h (with frame numbers),
 * SIGUSR1 pauses delivery (the host then sees a stalled camera) and SIGUSR2 resumes it, and when the
 * gadget goes away (UDC unbound: the gadget node returns ENODEV) it waits for the node to come back
 * and serves it again, so an unplug/replug test needs no restart.
 *
 * usage: uvcfeeder [-d /dev/videoN | -n INDEX] [-c] [-s INTERFACE] [-w W] [-h H] [-m maxpayload]
 *                  [-r fps (default 10)] [-k N] [-v]
 *   Without -d it serves the INDEX-th (default 0) video node whose driver is "g_uvc": one per UVC function,
 *   numbered in the order the gadget binds them, also after an unbind. -c sends the YUYV colour pattern
 *   of test_pattern.h instead of the depth pattern; -s is the function's VideoStreaming interface number
 *   (default 1, the first function's). Frames go out on a grid of the period on CLOCK_MONOTONIC, so that
 *   feeders of two functions at one rate send each frame together, as a camera's two sensors would.
 *   -k N: while skipping is on (SIGRTMIN turns it on, SIGRTMIN+1 off), every frame whose number is a
 *   multiple of N goes out short, half its bytes: uvcvideo drops a frame shorter than the committed size
 *   as corrupt, yet its sequence counter counts it, so the host's v4l2 sequence has a gap exactly there
 *   (frames a camera lost on the way, as the host sees them).
 * It answers the UVC class requests that the host (uvcvideo) sends: VS PROBE/COMMIT, and the VideoControl
 * requests of the controls 6.1's f_uvc declares (see vc_controls); once the host starts
 * streaming (UVC_EVENT_STREAMON) it queues frames.  On the original kernel 6.1
 * gadget the V4L2 side only accepts YUYV/MJPEG, so it falls back to YUYV (also
 * 16 bpp: the same bytes); the host sees the guidFormat configfs advertised (Z16).
 */
#include "test_pattern.h"

#include <errno.h>
#include <fcntl.h>
#include <linux/usb/ch9.h>
#include <linux/usb/g_uvc.h>
#include <linux/usb/video.h>
#include <linux/videodev2.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <sys/select.h>
#include <time.h>
#include <unistd.h>

static unsigned W = 640, H = 480, MAXPAYLOAD = 3072;
static int verbose;
static int colour;            /* -c: the colour pattern (YUYV) */
static unsigned node_index;   /* -n: which g_uvc node */
static unsigned vs_intf = 1;  /* -s: the VideoStreaming interface whose requests are ours */
static int fd;
static int streaming;
static unsigned nbufs;
static void *mem[8];
static size_t memlen[8];
static unsigned seq;
static volatile sig_atomic_t paused, resumed;
static volatile sig_atomic_t skipping; /* SIGRTMIN / SIGRTMIN+1 */
static unsigned skip_every;            /* -k */
static int holding;          /* paused: sent buffers are kept back */
static unsigned held[8], nheld; /* sent buffers waiting for their next frame's time */
static double period_s = 1.0 / 10; /* -r: frames per second (TCG has no time to spare for more) */
static double next_due;
static struct uvc_streaming_control probe, commit;
static int pending_cs; /* control selector of a pending SET_CUR */

/* The VideoControl side. 6.1's f_uvc declares fixed units (f_uvc.c uvc_alloc_inst; their bmControls are
 * read-only in configfs): camera terminal 1 with the auto-exposure mode, processing unit 2 with brightness,
 * output terminal 3 with none. Gain and exposure time cannot be declared there, so they are not here. */
enum { CAMERA_TERMINAL = 1, PROCESSING_UNIT = 2, OUTPUT_TERMINAL = 3 };

/* UVC 1.5 table 4-7: what VC_REQUEST_ERROR_CODE_CONTROL reports of the request before it */
enum {
	VC_ERROR_NONE = 0x00,
	VC_ERROR_OUT_OF_RANGE = 0x04,
	VC_ERROR_INVALID_UNIT = 0x05,
	VC_ERROR_INVALID_CONTROL = 0x06,
	VC_ERROR_INVALID_REQUEST = 0x07,
	VC_ERROR_INVALID_VALUE = 0x08,
};

struct vc_control {
	const char *name;
	uint8_t unit, selector, size;
	uint8_t bitmap; /* a set of modes (GET_RES names those offered; no GET_MIN/MAX), else a signed integer */
	int32_t min, max, res, def, cur;
};

/* Brightness: -64..64 as many webcams have it, default 0; its offset from the default shows in the depth
 * pattern (test_pattern.h dc_lit_pattern), not in the colour one, whose bytes spell coordinates. */
static struct vc_control brightness = {"brightness", PROCESSING_UNIT, UVC_PU_BRIGHTNESS_CONTROL, 2, 0,
				       -64, 64, 1, 0, 0};
/* Auto-exposure mode: manual (1) and aperture priority (8, the default), as most webcams offer; with no
 * exposure time declared it changes nothing in the pattern. */
static struct vc_control ae_mode = {"auto-exposure mode", CAMERA_TERMINAL, UVC_CT_AE_MODE_CONTROL, 1, 1,
				    0, 0, 0x09, 8, 8};
static struct vc_control *const vc_controls[] = {&brightness, &ae_mode};
static struct vc_control *pending_vc; /* the control of a pending VC SET_CUR, NULL for a VS one */
static uint8_t vc_error;              /* the last VC request's error code */

static void fill_ctrl(struct uvc_streaming_control *c)
{
	memset(c, 0, sizeof *c);
	c->bmHint = 1;
	c->bFormatIndex = 1;
	c->bFrameIndex = 1;
	c->dwFrameInterval = 333333; /* 30 fps */
	c->dwMaxVideoFrameSize = W * H * 2;
	c->dwMaxPayloadTransferSize = MAXPAYLOAD;
	c->bmFramingInfo = 3;
	c->bPreferedVersion = 1;
	c->bMaxVersion = 1;
}

static void fill_frame(void *p, size_t len)
{
	(void)len;
	if (colour)
		dc_fill_colour_pattern(p, W, H);
	else
		dc_fill_pattern(p, W, H, W, seq, brightness.cur - brightness.def);
	seq++;
}

static double now_s(void)
{
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return (double)t.tv_sec + (double)t.tv_nsec / 1e9;
}

static void on_signal(int sig)
{
	if (sig == SIGUSR1)
		paused = 1;
	else if (sig == SIGUSR2)
		resumed = 1;
	else
		skipping = sig == SIGRTMIN;
}

static void queue_frame(unsigned index)
{
	struct v4l2_buffer b = {.index = index, .type = V4L2_BUF_TYPE_VIDEO_OUTPUT, .memory = V4L2_MEMORY_MMAP};
	const unsigned number = seq;
	fill_frame(mem[index], memlen[index]);
	const int skip = skipping && skip_every && number % skip_every == 0;
	b.bytesused = skip ? W * H : W * H * 2;
	if (skip) {
		printf("feeder: frame %u sent short (skipped)\n", number);
		fflush(stdout);
	}
	if (ioctl(fd, VIDIOC_QBUF, &b) < 0)
		perror("feeder: QBUF");
}

static void stream_off(void)
{
	int type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
	if (!streaming)
		return;
	ioctl(fd, VIDIOC_STREAMOFF, &type);
	for (unsigned i = 0; i < nbufs; i++)
		munmap(mem[i], memlen[i]);
	struct v4l2_requestbuffers rb = {.count = 0, .type = V4L2_BUF_TYPE_VIDEO_OUTPUT,
					 .memory = V4L2_MEMORY_MMAP};
	ioctl(fd, VIDIOC_REQBUFS, &rb);
	streaming = 0;
	nheld = 0;
	printf("feeder: stream off after %u frames\n", seq);
	fflush(stdout);
}

static int stream_on(void)
{
	struct v4l2_format f = {.type = V4L2_BUF_TYPE_VIDEO_OUTPUT};
	f.fmt.pix.width = W;
	f.fmt.pix.height = H;
	/* Newer gadgets (6.1.1xx stable backports, >= 6.3) take the format from configfs
	 * (guidFormat -> fourcc), so ask for Z16; the original 6.1 gadget only knows
	 * YUYV/MJPEG, so fall back to YUYV (also 16 bpp: the same bytes go out). */
	static const uint32_t try_fcc[] = {V4L2_PIX_FMT_Z16, V4L2_PIX_FMT_YUYV};
	int ok = 0;
	for (unsigned i = colour ? 1 : 0; i < 2 && !ok; i++) {
		f.fmt.pix.pixelformat = try_fcc[i];
		f.fmt.pix.field = V4L2_FIELD_NONE;
		f.fmt.pix.sizeimage = W * H * 2;
		if (ioctl(fd, VIDIOC_S_FMT, &f) >= 0)
			ok = 1;
		else
			printf("feeder: gadget S_FMT %.4s: %s\n", (char *)&try_fcc[i], strerror(errno));
	}
	if (!ok)
		return -1;
	printf("feeder: gadget format %.4s %ux%u sizeimage=%u\n", (char *)&f.fmt.pix.pixelformat,
	       f.fmt.pix.width, f.fmt.pix.height, f.fmt.pix.sizeimage);
	/* note: f_uvc's REQBUFS returns the buffer count (> 0) on success */
	struct v4l2_requestbuffers rb = {.count = 4, .type = V4L2_BUF_TYPE_VIDEO_OUTPUT,
					 .memory = V4L2_MEMORY_MMAP};
	if (ioctl(fd, VIDIOC_REQBUFS, &rb) < 0) {
		perror("feeder: REQBUFS");
		return -1;
	}
	nbufs = rb.count > 8 ? 8 : rb.count;
	for (unsigned i = 0; i < nbufs; i++) {
		struct v4l2_buffer b = {.index = i, .type = V4L2_BUF_TYPE_VIDEO_OUTPUT,
					.memory = V4L2_MEMORY_MMAP};
		if (ioctl(fd, VIDIOC_QUERYBUF, &b) < 0) {
			perror("feeder: QUERYBUF");
			return -1;
		}
		memlen[i] = b.length;
		mem[i] = mmap(NULL, b.length, PROT_READ | PROT_WRITE, MAP_SHARED, fd, b.m.offset);
		if (mem[i] == MAP_FAILED) {
			perror("feeder: mmap");
			return -1;
		}
		fill_frame(mem[i], b.length);
		b.bytesused = W * H * 2;
		if (ioctl(fd, VIDIOC_QBUF, &b) < 0) {
			perror("feeder: QBUF");
			return -1;
		}
	}
	int type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
	if (ioctl(fd, VIDIOC_STREAMON, &type) < 0) {
		perror("feeder: STREAMON");
		return -1;
	}
	streaming = 1;
	printf("feeder: streaming %ux%u, %u buffers\n", W, H, nbufs);
	fflush(stdout);
	return 0;
}

/* A camera powers up with its controls at their defaults: a replugged gadget starts from them too. */
static void reset_controls(void)
{
	for (unsigned i = 0; i < sizeof vc_controls / sizeof vc_controls[0]; i++)
		vc_controls[i]->cur = vc_controls[i]->def;
	vc_error = VC_ERROR_NONE;
}

static struct vc_control *find_control(unsigned unit, unsigned selector)
{
	for (unsigned i = 0; i < sizeof vc_controls / sizeof vc_controls[0]; i++)
		if (vc_controls[i]->unit == unit && vc_controls[i]->selector == selector)
			return vc_controls[i];
	return NULL;
}

/* Puts a value little-endian into the reply, as many bytes as the control has or the host asked for. */
static void reply_value(struct uvc_request_data *resp, int32_t value, unsigned size, unsigned asked)
{
	for (unsigned i = 0; i < size; i++)
		resp->data[i] = (uint8_t)((uint32_t)value >> (8 * i));
	resp->length = (int)(asked < size ? asked : size);
}

/* Answers one request to a declared control and returns its error code: any but VC_ERROR_NONE leaves the
 * reply a stall. */
static uint8_t answer_control(struct vc_control *c, const struct usb_ctrlrequest *ctrl,
			      struct uvc_request_data *resp)
{
	switch (ctrl->bRequest) {
	case UVC_SET_CUR:
		if (ctrl->wLength != c->size)
			return VC_ERROR_INVALID_REQUEST;
		pending_vc = c;
		resp->length = c->size; /* the value arrives as UVC_EVENT_DATA */
		return VC_ERROR_NONE;
	case UVC_GET_CUR: reply_value(resp, c->cur, c->size, ctrl->wLength); return VC_ERROR_NONE;
	case UVC_GET_RES: reply_value(resp, c->res, c->size, ctrl->wLength); return VC_ERROR_NONE;
	case UVC_GET_DEF: reply_value(resp, c->def, c->size, ctrl->wLength); return VC_ERROR_NONE;
	case UVC_GET_INFO:
		reply_value(resp, UVC_CONTROL_CAP_GET | UVC_CONTROL_CAP_SET, 1, ctrl->wLength);
		return VC_ERROR_NONE;
	case UVC_GET_LEN: reply_value(resp, c->size, 2, ctrl->wLength); return VC_ERROR_NONE;
	case UVC_GET_MIN:
	case UVC_GET_MAX:
		if (c->bitmap)
			return VC_ERROR_INVALID_REQUEST;
		reply_value(resp, ctrl->bRequest == UVC_GET_MIN ? c->min : c->max, c->size, ctrl->wLength);
		return VC_ERROR_NONE;
	}
	return VC_ERROR_INVALID_REQUEST;
}

/* A VideoControl request: wIndex's high byte names the unit, 0 the interface itself, whose one control is
 * the error code of the request before (read-only; reading it leaves it as it is). Whatever is not
 * answered stalls, and the error code says why, as UVC 1.5 section 4.2.1.2 asks. */
static void handle_vc(const struct usb_ctrlrequest *ctrl, struct uvc_request_data *resp)
{
	const unsigned unit = ctrl->wIndex >> 8, cs = ctrl->wValue >> 8;
	if (unit == 0 && cs == UVC_VC_REQUEST_ERROR_CODE_CONTROL) {
		if (ctrl->bRequest == UVC_GET_CUR)
			reply_value(resp, vc_error, 1, ctrl->wLength);
		else if (ctrl->bRequest == UVC_GET_INFO)
			reply_value(resp, UVC_CONTROL_CAP_GET, 1, ctrl->wLength);
		else
			vc_error = VC_ERROR_INVALID_REQUEST;
		return;
	}
	struct vc_control *c = find_control(unit, cs);
	if (c)
		vc_error = answer_control(c, ctrl, resp);
	else if (unit == CAMERA_TERMINAL || unit == PROCESSING_UNIT || unit == OUTPUT_TERMINAL)
		vc_error = VC_ERROR_INVALID_CONTROL;
	else
		vc_error = VC_ERROR_INVALID_UNIT;
}

/* A VideoStreaming request: probe and commit of the one format and frame. */
static void handle_vs(const struct usb_ctrlrequest *ctrl, struct uvc_request_data *resp)
{
	unsigned cs = ctrl->wValue >> 8;
	unsigned len = ctrl->wLength;
	if (cs != UVC_VS_PROBE_CONTROL && cs != UVC_VS_COMMIT_CONTROL)
		return;
	struct uvc_streaming_control *c = cs == UVC_VS_PROBE_CONTROL ? &probe : &commit;
	unsigned sz = sizeof *c;
	switch (ctrl->bRequest) {
	case UVC_SET_CUR:
		pending_cs = cs;
		pending_vc = NULL;
		resp->length = len < sz ? len : sz; /* data arrives as UVC_EVENT_DATA */
		break;
	case UVC_GET_CUR:
	case UVC_GET_MIN:
	case UVC_GET_MAX:
	case UVC_GET_DEF: {
		struct uvc_streaming_control t;
		if (ctrl->bRequest == UVC_GET_CUR)
			t = *c;
		else
			fill_ctrl(&t);
		memcpy(resp->data, &t, sz);
		resp->length = len < sz ? len : sz;
		break;
	}
	case UVC_GET_RES:
		memset(resp->data, 0, sz);
		resp->length = len < sz ? len : sz;
		break;
	case UVC_GET_LEN:
		resp->data[0] = sz & 0xff;
		resp->data[1] = sz >> 8;
		resp->length = 2;
		break;
	case UVC_GET_INFO:
		resp->data[0] = 3;
		resp->length = 1;
		break;
	}
}

static void handle_setup(const struct usb_ctrlrequest *ctrl, struct uvc_request_data *resp)
{
	resp->length = -EL2HLT; /* default: stall */
	if (verbose)
		printf("feeder: setup bRequestType=%02x bRequest=%02x wValue=%04x wIndex=%04x wLength=%u\n",
		       ctrl->bRequestType, ctrl->bRequest, ctrl->wValue, ctrl->wIndex, ctrl->wLength);
	if ((ctrl->bRequestType & USB_TYPE_MASK) != USB_TYPE_CLASS)
		return;
	/* each function has a VideoControl interface and then its VideoStreaming one (-s) */
	unsigned intf = ctrl->wIndex & 0xff;
	if (intf == vs_intf)
		handle_vs(ctrl, resp);
	else if (intf + 1 == vs_intf)
		handle_vc(ctrl, resp);
}

/* The value of a VC SET_CUR. f_uvc on 6.1 has acknowledged its data stage before telling us, so a value
 * out of range cannot stall any more (uvcvideo clamps integers and checks menus before sending): it is left
 * unset, and the error code says why. */
static void set_control(struct vc_control *c, const struct uvc_request_data *d)
{
	if (d->length < c->size) {
		vc_error = VC_ERROR_INVALID_REQUEST;
		return;
	}
	const int32_t v = c->size == 1 ? d->data[0] : (int16_t)(d->data[0] | d->data[1] << 8);
	if (c->bitmap)
		vc_error = (v & c->res) == v && v && !(v & (v - 1)) ? VC_ERROR_NONE : VC_ERROR_INVALID_VALUE;
	else
		vc_error = v >= c->min && v <= c->max && (v - c->min) % c->res == 0 ? VC_ERROR_NONE
										      : VC_ERROR_OUT_OF_RANGE;
	if (vc_error == VC_ERROR_NONE)
		c->cur = v;
	printf("feeder: SET_CUR %s = %d%s\n", c->name, v, vc_error ? " refused" : "");
}

static void handle_data(const struct uvc_request_data *d)
{
	if (pending_vc) {
		set_control(pending_vc, d);
		pending_vc = NULL;
		return;
	}
	struct uvc_streaming_control *c = pending_cs == UVC_VS_COMMIT_CONTROL ? &commit : &probe;
	struct uvc_streaming_control in;
	fill_ctrl(&in);
	memcpy(&in, d->data, d->length < (int)sizeof in ? (size_t)d->length : sizeof in);
	/* we support exactly one format/frame: clamp to it */
	fill_ctrl(c);
	if (in.dwFrameInterval)
		c->dwFrameInterval = in.dwFrameInterval;
	if (verbose || pending_cs == UVC_VS_COMMIT_CONTROL)
		printf("feeder: SET_CUR %s fmt=%u frame=%u interval=%u\n",
		       pending_cs == UVC_VS_COMMIT_CONTROL ? "COMMIT" : "PROBE", in.bFormatIndex,
		       in.bFrameIndex, in.dwFrameInterval);
	fflush(stdout);
}

static void serve(const char *dev);

static int find_gadget_node(char *out, size_t n)
{
	unsigned seen = 0;
	for (int i = 0; i < 16; i++) {
		char p[32];
		snprintf(p, sizeof p, "/dev/video%d", i);
		int f = open(p, O_RDWR | O_NONBLOCK);
		if (f < 0)
			continue;
		struct v4l2_capability cap = {0};
		int ok = ioctl(f, VIDIOC_QUERYCAP, &cap) == 0 && !strcmp((char *)cap.driver, "g_uvc");
		close(f);
		if (ok && seen++ == node_index) {
			snprintf(out, n, "%s", p);
			return 0;
		}
	}
	return -1;
}

int main(int argc, char **argv)
{
	char dev[32] = "";
	int opt;
	while ((opt = getopt(argc, argv, "d:n:cs:w:h:m:r:k:v")) != -1) {
		switch (opt) {
		case 'd': snprintf(dev, sizeof dev, "%s", optarg); break;
		case 'n': node_index = (unsigned)atoi(optarg); break;
		case 'c': colour = 1; break;
		case 's': vs_intf = (unsigned)atoi(optarg); break;
		case 'w': W = atoi(optarg); break;
		case 'h': H = atoi(optarg); break;
		case 'm': MAXPAYLOAD = atoi(optarg); break;
		case 'r': period_s = 1.0 / atof(optarg); break;
		case 'k': skip_every = (unsigned)atoi(optarg); break;
		case 'v': verbose = 1; break;
		default: return 2;
		}
	}
	if (!dev[0] && find_gadget_node(dev, sizeof dev)) {
		fprintf(stderr, "feeder: no g_uvc video node found\n");
		return 1;
	}
	fill_ctrl(&probe);
	fill_ctrl(&commit);
	signal(SIGUSR1, on_signal);
	signal(SIGUSR2, on_signal);
	signal(SIGRTMIN, on_signal);
	signal(SIGRTMIN + 1, on_signal);
	for (;;) {
		serve(dev);
		/* the gadget went away (UDC unbound): wait for it to be bound again */
		close(fd);
		printf("feeder: gadget gone after %u frames, waiting for it\n", seq);
		fflush(stdout);
		while (find_gadget_node(dev, sizeof dev))
			usleep(100000);
	}
}

/* Serves one gadget node until it goes away. */
static void serve(const char *dev)
{
	fd = open(dev, O_RDWR | O_NONBLOCK); /* opening activates the gadget: host enumerates now */
	if (fd < 0) {
		perror("feeder: open");
		return;
	}
	reset_controls();
	static const unsigned evs[] = {UVC_EVENT_SETUP, UVC_EVENT_DATA, UVC_EVENT_STREAMON,
				       UVC_EVENT_STREAMOFF, UVC_EVENT_CONNECT, UVC_EVENT_DISCONNECT};
	for (unsigned i = 0; i < sizeof evs / sizeof evs[0]; i++) {
		struct v4l2_event_subscription s = {.type = evs[i]};
		if (ioctl(fd, VIDIOC_SUBSCRIBE_EVENT, &s) < 0)
			perror("feeder: SUBSCRIBE_EVENT");
	}
	printf("feeder: serving %s (%ux%u)\n", dev, W, H);
	fflush(stdout);
	signal(SIGPIPE, SIG_IGN);
	/* pause/resume and skip signals are only let in while waiting in pselect, so none is missed */
	sigset_t block, waitmask;
	sigemptyset(&block);
	sigaddset(&block, SIGUSR1);
	sigaddset(&block, SIGUSR2);
	sigaddset(&block, SIGRTMIN);
	sigaddset(&block, SIGRTMIN + 1);
	sigprocmask(SIG_BLOCK, &block, &waitmask);
	sigdelset(&waitmask, SIGUSR1);
	sigdelset(&waitmask, SIGUSR2);
	sigdelset(&waitmask, SIGRTMIN);
	sigdelset(&waitmask, SIGRTMIN + 1);
	for (;;) {
		if (paused) {
			paused = 0;
			printf("feeder: paused (holding buffers)\n");
			fflush(stdout);
			holding = 1;
		}
		if (resumed) {
			resumed = 0;
			holding = 0;
			printf("feeder: resumed\n");
			fflush(stdout);
		}
		/* paced delivery: one held buffer goes back with a new frame each period */
		double now = now_s();
		if (!holding && nheld && now >= next_due) {
			queue_frame(held[0]);
			memmove(held, held + 1, --nheld * sizeof held[0]);
			next_due = ((double)(long long)(now / period_s) + 1.0) * period_s; /* the next tick of the grid */
		}
		struct timespec wait = {0, 0}, *waitp = NULL;
		if (!holding && nheld) {
			double left = next_due - now_s();
			if (left > 0) {
				wait.tv_sec = (time_t)left;
				wait.tv_nsec = (long)((left - (double)wait.tv_sec) * 1e9);
			}
			waitp = &wait;
		}
		fd_set efds, wfds;
		FD_ZERO(&efds);
		FD_ZERO(&wfds);
		FD_SET(fd, &efds);
		if (streaming)
			FD_SET(fd, &wfds);
		int r = pselect(fd + 1, NULL, &wfds, &efds, waitp, &waitmask);
		if (r < 0) {
			if (errno == EINTR)
				continue;
			perror("feeder: select");
			return;
		}
		if (FD_ISSET(fd, &efds)) {
			struct v4l2_event ev;
			int got = 0;
			while (ioctl(fd, VIDIOC_DQEVENT, &ev) == 0) {
				got = 1;
				struct uvc_event *uev = (void *)&ev.u.data;
				struct uvc_request_data resp;
				switch (ev.type) {
				case UVC_EVENT_CONNECT:
					printf("feeder: connect (speed %d)\n", uev->speed);
					break;
				case UVC_EVENT_DISCONNECT:
					printf("feeder: disconnect\n");
					stream_off();
					break;
				case UVC_EVENT_SETUP:
					memset(&resp, 0, sizeof resp);
					handle_setup(&uev->req, &resp);
					if (ioctl(fd, UVCIOC_SEND_RESPONSE, &resp) < 0)
						perror("feeder: SEND_RESPONSE");
					break;
				case UVC_EVENT_DATA:
					handle_data(&uev->data);
					break;
				case UVC_EVENT_STREAMON:
					printf("feeder: host STREAMON\n");
					stream_on();
					break;
				case UVC_EVENT_STREAMOFF:
					printf("feeder: host STREAMOFF\n");
					stream_off();
					break;
				}
				fflush(stdout);
			}
			if (!got && errno == ENODEV) { /* unregistered: the UDC was unbound */
				stream_off();
				return;
			}
		}
		if (streaming && FD_ISSET(fd, &wfds)) {
			struct v4l2_buffer b = {.type = V4L2_BUF_TYPE_VIDEO_OUTPUT, .memory = V4L2_MEMORY_MMAP};
			if (ioctl(fd, VIDIOC_DQBUF, &b) >= 0) {
				if (nheld < 8)
					held[nheld++] = b.index;
			} else if (errno == ENODEV) {
				stream_off();
				return;
			} else if (errno != EAGAIN) {
				perror("feeder: DQBUF");
				stream_off();
			}
		}
	}
}
