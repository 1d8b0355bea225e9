// The web page's image lookups: explicit texel fetches and weights (no GPU filtering, whose
// weights are 8-bit fractions), core/sampling.py's sample_bilinear; the GLSL twin of
// osl/dp_tex.h.

vec3 dp_srgb_to_linear(vec3 c)
{
    vec3 hi = pow((max(c, vec3(0.04045)) + 0.055) / 1.055, vec3(2.4));
    return mix(hi, c / 12.92, vec3(lessThanEqual(c, vec3(0.04045))));
}

// A texel index k into [0, n) by the lookup's extension: 0 REPEAT, 1 EXTEND, 2 MIRROR
// (core/sampling.py wrap_index).
int dp_wrap(int k, int n, int wrap)
{
    if (wrap == 1) return clamp(k, 0, n - 1);
    int period = wrap == 0 ? n : 2 * n;
    int m = k % period;
    if (m < 0) m += period;
    return m >= n ? 2 * n - 1 - m : m;
}

vec4 dp_texel(sampler2D s, int srgb, ivec2 size, int i, int j, int wrap)
{
    vec4 c = texelFetch(s, ivec2(dp_wrap(j, size.x, wrap), dp_wrap(i, size.y, wrap)), 0);
    return srgb == 1 ? vec4(dp_srgb_to_linear(c.rgb), c.a) : c;
}

// An image at a UV (v up, row 0 of the texture at the bottom): interp 0 linear between texel
// centres, 1 closest. Colour images holding sRGB codes (srgb 1) are decoded texel by texel.
vec3 dp_tex(sampler2D s, int srgb, vec3 uv, int wrap, int interp, out float a)
{
    ivec2 size = textureSize(s, 0);
    vec2 p = uv.xy * vec2(size);
    // a bad warp reads a texel, never fails (core/sampling.py: a non-finite coordinate is 0)
    p.x = isnan(p.x) || isinf(p.x) ? 0.5 : p.x;
    p.y = isnan(p.y) || isinf(p.y) ? 0.5 : p.y;
    p = clamp(p, vec2(-16777216.0), vec2(16777216.0));
    vec4 c;
    if (interp == 1) {
        c = dp_texel(s, srgb, size, int(floor(p.y)), int(floor(p.x)), wrap);
    } else {
        p -= 0.5;
        vec2 p0 = floor(p);
        vec2 f = p - p0;
        int i = int(p0.y), j = int(p0.x);
        vec4 bottom = mix(dp_texel(s, srgb, size, i, j, wrap), dp_texel(s, srgb, size, i, j + 1, wrap), f.x);
        vec4 top = mix(dp_texel(s, srgb, size, i + 1, j, wrap), dp_texel(s, srgb, size, i + 1, j + 1, wrap), f.x);
        c = mix(bottom, top, f.y);
    }
    a = c.a;
    return c.rgb;
}

// An image at (u, v), linear between texel centres, edges extended: what the march reads.
vec3 dp_image_at(sampler2D s, int srgb, float u, float v)
{
    float a;
    return dp_tex(s, srgb, vec3(u, v, 0.0), 1, 0, a);
}
