/* test_pattern.h - the 16-bit depth pattern the in-guest feeders send and the guest test checks.
 * Pixel (0,0) and (1,0) carry the frame number (low and high 16 bits), so a reader knows which frame
 * it got; every other pixel changes with the frame. Also the colour pattern of the camera's colour stream.
 * Shared by C (feeders) and C++ (guest test). */
#ifndef DC_TEST_PATTERN_H
#define DC_TEST_PATTERN_H
#include <stddef.h>
#include <stdint.h>

static inline uint16_t dc_pattern(unsigned x, unsigned y, unsigned frame)
{
	if (y == 0 && x == 0)
		return (uint16_t)(frame & 0xffffu);
	if (y == 0 && x == 1)
		return (uint16_t)(frame >> 16);
	return (uint16_t)(x * 3u + y * 5u + frame * 7u);
}

/* The depth pattern as the UVC feeder sends it under a brightness (its processing unit's control): the
 * brightness minus its default is added to every pixel but the frame number's two, modulo 2^16, so one frame
 * tells which brightness was in effect when it was made. */
static inline uint16_t dc_lit_pattern(unsigned x, unsigned y, unsigned frame, int brightness_offset)
{
	const uint16_t raw = dc_pattern(x, y, frame);
	return y == 0 && x < 2 ? raw : (uint16_t)(raw + (unsigned)brightness_offset);
}

static inline void dc_fill_pattern(uint16_t *px, unsigned w, unsigned h, unsigned stride_px, unsigned frame,
				   int brightness_offset)
{
	for (unsigned y = 0; y < h; y++)
		for (unsigned x = 0; x < w; x++)
			px[y * stride_px + x] = dc_lit_pattern(x, y, frame, brightness_offset);
}

/* The colour pattern: packed YUYV whose bytes spell each pixel's own coordinates, so a reader of any one
 * pixel knows where in the image it came from. Y = x & 0xff per pixel; a pixel pair shares its chroma,
 * and both of a pair have the same y and x >> 8: U = y, V = 64 below x = 256 and 192 from there. Images
 * up to 512x256. */
static inline void dc_fill_colour_pattern(uint8_t *yuyv, unsigned w, unsigned h)
{
	for (unsigned y = 0; y < h; y++)
		for (unsigned x = 0; x + 1 < w; x += 2) {
			uint8_t *p = yuyv + ((size_t)y * w + x) * 2;
			p[0] = (uint8_t)(x & 0xffu);
			p[1] = (uint8_t)y;
			p[2] = (uint8_t)((x + 1) & 0xffu);
			p[3] = (uint8_t)(x >= 256 ? 192 : 64);
		}
}

/* The coordinates the colour pattern's pixel (x, y) spells. */
static inline void dc_colour_pattern_at(const uint8_t *yuyv, unsigned w, unsigned x, unsigned y, unsigned *px,
					unsigned *py)
{
	const uint8_t *pair = yuyv + ((size_t)y * w + (x & ~1u)) * 2;
	*px = pair[(x & 1u) * 2] + (pair[3] >= 128 ? 256u : 0u);
	*py = pair[1];
}
#endif
