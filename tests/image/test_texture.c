/* tests/image/test_texture.c - pictures read as 8-bit RGBA (hv_rgba8_decode): PNG of every colour
 * type with its iCCP profile, JPEG (baseline, progressive, grey, with an ICC profile) written by
 * Python's Pillow into the fuzz corpus, against the values they were written with; damaged, CMYK
 * and oversized pictures refused with one message. */
#include <criterion/criterion.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/image.h"
#include "support/support.h"

static hv_status decode(const char *file, uint64_t max, hv_rgba8 *img)
{
    char path[256];
    snprintf(path, sizeof path, "tests/fuzz/corpus/texture/%s", file);
    size_t n = 0;
    char *data = t_slurp(path, &n);
    hv_status s = hv_rgba8_decode(data, n, file, max, img);
    free(data);
    return s;
}

static void pixel(const hv_rgba8 *img, int x, int y, int r, int g, int b, int a, int tol)
{
    const uint8_t *p = img->rgba + 4 * ((size_t)y * (size_t)img->width + (size_t)x);
    int want[4] = {r, g, b, a};
    for (int k = 0; k < 4; ++k)
        cr_assert(abs(p[k] - want[k]) <= tol, "(%d, %d) channel %d: %d, expected %d", x, y, k, p[k], want[k]);
}

Test(texture, png_colour_types_and_the_embedded_profile)
{
    hv_rgba8 img;
    cr_assert_eq(decode("rgba.png", 1000, &img), HV_OK, "%s", hv_last_error());
    cr_assert_eq(img.width, 2);
    pixel(&img, 0, 0, 255, 0, 0, 255, 0);
    pixel(&img, 1, 0, 0, 255, 0, 128, 0);
    cr_assert_null(img.icc);
    hv_rgba8_free(&img);
    cr_assert_eq(decode("grey16.png", 1000, &img), HV_OK, "%s", hv_last_error());
    pixel(&img, 0, 0, 255, 255, 255, 255, 0);
    pixel(&img, 0, 1, 0x12, 0x12, 0x12, 255, 0); /* 0x1234 / 257 rounds to 0x12 */
    hv_rgba8_free(&img);
    cr_assert_eq(decode("iccp.png", 1000, &img), HV_OK, "%s", hv_last_error());
    pixel(&img, 0, 0, 1, 2, 3, 255, 0);
    size_t n = 0;
    char *icc = t_slurp("/usr/share/color/icc/ghostscript/default_rgb.icc", &n);
    cr_assert_eq(img.icc_size, n);
    cr_assert_eq(memcmp(img.icc, icc, n), 0);
    free(icc);
    hv_rgba8_free(&img);
    cr_assert_eq(decode("iccp_broken.png", 1000, &img), HV_OK, "%s", hv_last_error());
    cr_assert_null(img.icc); /* a profile that does not inflate is ignored, as libpng does */
    hv_rgba8_free(&img);
}

Test(texture, jpeg_baseline_progressive_grey_and_profile)
{
    hv_rgba8 img;
    cr_assert_eq(decode("flat.jpg", 1000, &img), HV_OK, "%s", hv_last_error());
    cr_assert_eq(img.width, 16);
    cr_assert_eq(img.height, 8);
    pixel(&img, 7, 3, 200, 100, 50, 255, 2);
    hv_rgba8_free(&img);
    cr_assert_eq(decode("progressive.jpg", 1000, &img), HV_OK, "%s", hv_last_error());
    pixel(&img, 0, 0, 10, 20, 30, 255, 2);
    hv_rgba8_free(&img);
    cr_assert_eq(decode("grey.jpg", 1000, &img), HV_OK, "%s", hv_last_error());
    pixel(&img, 4, 4, 77, 77, 77, 255, 1);
    hv_rgba8_free(&img);
    cr_assert_eq(decode("icc.jpg", 1000, &img), HV_OK, "%s", hv_last_error());
    cr_assert_not_null(img.icc);
    cr_assert_eq(memcmp(img.icc + 36, "acsp", 4), 0); /* an ICC profile's signature */
    hv_rgba8_free(&img);
}

Test(texture, refusals)
{
    hv_rgba8 img;
    cr_assert_eq(decode("truncated.jpg", 1000, &img), HV_ERR_BAD_INPUT);
    cr_assert(strncmp(hv_last_error(), "truncated.jpg: not a readable JPEG: ", 36) == 0, "%s", hv_last_error());
    cr_assert_null(img.rgba);
    cr_assert_eq(decode("cmyk.jpg", 1000, &img), HV_ERR_BAD_INPUT);
    cr_assert_str_eq(hv_last_error(), "cmyk.jpg: a CMYK JPEG (textures are RGB or grey)");
    cr_assert_eq(decode("text.txt", 1000, &img), HV_ERR_BAD_INPUT);
    cr_assert_str_eq(hv_last_error(), "text.txt: not an image (neither PNG nor JPEG)");
    cr_assert_eq(decode("flat.jpg", 100, &img), HV_ERR_LIMIT);
    cr_assert_str_eq(hv_last_error(), "flat.jpg: a picture of 16 x 8 pixels is larger than allowed here (100 pixels)");
    cr_assert_eq(decode("huge.png", 1000, &img), HV_ERR_LIMIT);
    hv_rgba8_free(NULL);
}
