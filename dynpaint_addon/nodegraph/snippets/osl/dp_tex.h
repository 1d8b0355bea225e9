// The OSL shader's image lookups: files read by OIIO, and the painting's UV.

// An image: its file and its size in texels (the shader's `<channel>_width/_height` inputs,
// set by the add-on: OSL's gettextureinfo crashes Cycles in Blender 5.3).
struct dp_image { string file; int w; int h; };
#define DP_IMAGE dp_image

float dp_srgb_to_linear(float c)
{
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

// The painting's UV, (u, v) ∈ [0, 1]² over the plane, v up: the shader's `painting_uv` input,
// linked to a Texture Coordinate node's UV (Cycles exports attributes a Script node reads
// by a computed name only if asked, so the UV comes in as a socket).
#define dp_uv() painting_uv

// Which way texture()'s t runs: down the image in Cycles up to Blender 5.1 (OIIO's own
// convention), up it from 5.2 on (blender-notes.md). The add-on defines it for the Blender it
// runs in; the default is the newer.
#ifndef DP_TEXTURE_T_DOWN
#define DP_TEXTURE_T_DOWN 0
#endif

// A texel index k into [0, n) by the lookup's extension: "periodic", "clamp" or "mirror"
// (core/sampling.py wrap_index). Done here, texel by texel: Cycles from Blender 5.2 on ignores
// texture()'s "wrap" (black outside [0, 1]; blender-notes.md).
int dp_wrap(int k, int n, string wrap)
{
    if (wrap == "clamp")
        return k < 0 ? 0 : (k > n - 1 ? n - 1 : k);
    int period = wrap == "periodic" ? n : 2 * n;
    int m = k % period;
    if (m < 0)
        m += period;
    return m >= n ? 2 * n - 1 - m : m;
}

// Texel (row i from the bottom, column j) of an image, wrapped, linear (sRGB decoded).
vector dp_texel(dp_image img, int srgb, int i, int j, string wrap, output float a)
{
    float s = (dp_wrap(j, img.w, wrap) + 0.5) / img.w;
    float t = (dp_wrap(i, img.h, wrap) + 0.5) / img.h;
#if DP_TEXTURE_T_DOWN
    t = 1.0 - t;
#endif
    a = 1.0;
    color c = texture(img.file, s, t, "interp", "closest", "width", 0.0, "alpha", a,
                      "fill", 1.0);
    if (srgb != 0)
        c = color(dp_srgb_to_linear(c[0]), dp_srgb_to_linear(c[1]), dp_srgb_to_linear(c[2]));
    return vector(c);
}

// An image at a UV (v up): "linear" between texel centres, or "closest"; texels decoded,
// then weighed, as core/sampling.py's sample_bilinear (the web page's dp_tex is its twin).
vector dp_tex(dp_image img, int srgb, vector uv, string wrap, string interp, output float a)
{
    float px = uv[0] * img.w, py = uv[1] * img.h;
    // a bad warp reads a texel, never fails (core/sampling.py: a non-finite coordinate is 0)
    px = isnan(px) || isinf(px) ? 0.5 : clamp(px, -16777216.0, 16777216.0);
    py = isnan(py) || isinf(py) ? 0.5 : clamp(py, -16777216.0, 16777216.0);
    if (interp == "closest")
        return dp_texel(img, srgb, (int)floor(py), (int)floor(px), wrap, a);
    px -= 0.5;
    py -= 0.5;
    float x0 = floor(px), y0 = floor(py);
    float fx = px - x0, fy = py - y0;
    int i = (int)y0, j = (int)x0;
    float a00, a01, a10, a11;
    vector c00 = dp_texel(img, srgb, i, j, wrap, a00);
    vector c01 = dp_texel(img, srgb, i, j + 1, wrap, a01);
    vector c10 = dp_texel(img, srgb, i + 1, j, wrap, a10);
    vector c11 = dp_texel(img, srgb, i + 1, j + 1, wrap, a11);
    a = mix(mix(a00, a01, fx), mix(a10, a11, fx), fy);
    return mix(mix(c00, c01, fx), mix(c10, c11, fx), fy);
}

// An image at (u, v), linear between texel centres, edges extended: what the march reads.
vector dp_image_at(dp_image img, int srgb, float u, float v)
{
    float a;
    return dp_tex(img, srgb, vector(u, v, 0.0), "clamp", "linear", a);
}
