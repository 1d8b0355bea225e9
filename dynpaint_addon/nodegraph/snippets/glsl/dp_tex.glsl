// The web page's image lookups, the GLSL twin of osl/dp_tex.h. The GPU filters where it can
// do what the core does (issue 29): colour images arrive as sRGB textures (decoded to linear
// per texel before filtering, as core/sampling.py decodes then interpolates) or already
// linear, data images as linear textures; a lookup whose image the page lets the GPU filter
// (`hw` 1: a filterable format, the sampler's wrap set to this lookup's extension) is one
// hardware fetch. The others — Closest taps, a second extension of an image, float images
// where the browser cannot filter floats — fetch texels and weigh them here exactly:
// core/sampling.py's sample_bilinear.

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

vec4 dp_texel(sampler2D s, ivec2 size, int i, int j, int wrap)
{
    return texelFetch(s, ivec2(dp_wrap(j, size.x, wrap), dp_wrap(i, size.y, wrap)), 0);
}

// An image at a UV (v up, row 0 of the texture at the bottom): interp 0 linear between texel
// centres, 1 closest; texels are linear (sRGB textures are decoded by the GPU as fetched).
vec3 dp_tex(sampler2D s, vec3 uv, int wrap, int interp, out float a)
{
    ivec2 size = textureSize(s, 0);
    vec2 p = uv.xy * vec2(size);
    // a bad warp reads a texel, never fails (core/sampling.py: a non-finite coordinate is 0)
    p.x = isnan(p.x) || isinf(p.x) ? 0.5 : p.x;
    p.y = isnan(p.y) || isinf(p.y) ? 0.5 : p.y;
    p = clamp(p, vec2(-16777216.0), vec2(16777216.0));
    vec4 c;
    if (interp == 1) {
        c = dp_texel(s, size, int(floor(p.y)), int(floor(p.x)), wrap);
    } else {
        p -= 0.5;
        vec2 p0 = floor(p);
        vec2 f = p - p0;
        int i = int(p0.y), j = int(p0.x);
        vec4 bottom = mix(dp_texel(s, size, i, j, wrap), dp_texel(s, size, i, j + 1, wrap), f.x);
        vec4 top = mix(dp_texel(s, size, i + 1, j, wrap), dp_texel(s, size, i + 1, j + 1, wrap), f.x);
        c = mix(bottom, top, f.y);
    }
    a = c.a;
    return c.rgb;
}

// An image at a UV through the GPU's filter and wrap (hw 1), else as dp_tex. A bad warp reads
// a texel, never fails (core/sampling.py: a non-finite coordinate is 0).
vec3 dp_tex_hw(sampler2D s, int hw, vec3 uv, int wrap, int interp, out float a)
{
    if (hw == 1) {
        vec2 p = uv.xy;
        p.x = isnan(p.x) || isinf(p.x) ? 0.0 : p.x;
        p.y = isnan(p.y) || isinf(p.y) ? 0.0 : p.y;
        vec4 c = textureLod(s, p, 0.0);
        a = c.a;
        return c.rgb;
    }
    return dp_tex(s, uv, wrap, interp, a);
}

// An image at (u, v), linear between texel centres, edges extended: what the march reads
// (mode: 1 when the GPU filters the image, its sampler clamped to the edge).
vec3 dp_image_at(sampler2D s, int mode, float u, float v)
{
    float a;
    return dp_tex_hw(s, mode, vec3(u, v, 0.0), 1, 0, a);
}
