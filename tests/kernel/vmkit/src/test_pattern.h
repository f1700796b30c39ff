/* test_pattern.h - the 16-bit depth pattern the in-guest feeders send and the guest test checks.
 * Pixel (0,0) and (1,0) carry the frame number (low and high 16 bits), so a reader knows which frame
 * it got; every other pixel changes with the frame. Shared by C (feeders) and C++ (guest test). */
#ifndef DC_TEST_PATTERN_H
#define DC_TEST_PATTERN_H
#include <stdint.h>

static inline uint16_t dc_pattern(unsigned x, unsigned y, unsigned frame)
{
	if (y == 0 && x == 0)
		return (uint16_t)(frame & 0xffffu);
	if (y == 0 && x == 1)
		return (uint16_t)(frame >> 16);
	return (uint16_t)(x * 3u + y * 5u + frame * 7u);
}

static inline void dc_fill_pattern(uint16_t *px, unsigned w, unsigned h, unsigned stride_px, unsigned frame)
{
	for (unsigned y = 0; y < h; y++)
		for (unsigned x = 0; x < w; x++)
			px[y * stride_px + x] = dc_pattern(x, y, frame);
}
#endif
