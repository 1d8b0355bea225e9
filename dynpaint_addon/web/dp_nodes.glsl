// Blender's node semantics in GLSL ES 3.00, so generated code computes what the node trees
// compute (blender-notes.md: division by zero gives 0, Map Range at From Min = From Max gives
// To Min, normalizing (0, 0, 0) gives (0, 0, 0)): the GLSL twin of shaders_osl/dp_nodes.h.
// And the painting's texture lookups: explicit texel fetches and weights (no GPU filtering,
// whose weights are 8-bit fractions), core/sampling.py's sample_bilinear.

float dp_div(float a, float b) { return b != 0.0 ? a / b : 0.0; }
vec3 dp_vdiv(vec3 a, vec3 b) { return vec3(dp_div(a.x, b.x), dp_div(a.y, b.y), dp_div(a.z, b.z)); }
float dp_sqrt(float a) { return a > 0.0 ? sqrt(a) : 0.0; }
float dp_abs(float a) { return abs(a); }
float dp_sign(float a) { return a > 0.0 ? 1.0 : (a < 0.0 ? -1.0 : 0.0); }
float dp_pow(float a, float b)
{
    if (a > 0.0) return pow(a, b);
    if (a == 0.0) return b > 0.0 ? 0.0 : (b == 0.0 ? 1.0 : 0.0);
    float f = b - floor(b);          // negative base: integer exponents only (Blender's rule)
    if (f > 0.001 && f < 0.999) return 0.0;
    float e = floor(b + 0.5);
    float r = pow(-a, e);
    return mod(e, 2.0) == 1.0 ? -r : r;
}
float dp_compare(float a, float b, float eps) { return abs(a - b) <= max(eps, 1.1920929e-7) ? 1.0 : 0.0; }
vec3 dp_normalize(vec3 a) { float l = length(a); return l > 0.0 ? a / l : vec3(0.0); }
float dp_mix(float a, float b, float t) { return a * (1.0 - t) + b * t; }
vec3 dp_vmix(vec3 a, vec3 b, vec3 t) { return a * (vec3(1.0) - t) + b * t; }

float dp_smoothstep(float e0, float e1, float x)
{
    if (x < e0) return 0.0;
    if (x >= e1) return 1.0;
    float t = (x - e0) / (e1 - e0);
    return (3.0 - 2.0 * t) * (t * t);
}

float dp_map_range(float v, float fmin, float fmax, float tmin, float tmax, int interp, int clamp_)
{
    float factor = 0.0;
    if (interp == 0) {                       // linear
        factor = fmax != fmin ? (v - fmin) / (fmax - fmin) : 0.0;
    } else if (interp == 1) {                // smooth step
        factor = fmin > fmax ? 1.0 - dp_smoothstep(fmax, fmin, v) : dp_smoothstep(fmin, fmax, v);
    } else {                                 // smoother step
        float x = fmax != fmin ? clamp((v - fmin) / (fmax - fmin), 0.0, 1.0) : 0.0;
        factor = x * x * x * (x * (x * 6.0 - 15.0) + 10.0);
    }
    float r = tmin + factor * (tmax - tmin);
    if (clamp_ == 1 && interp == 0) r = clamp(r, min(tmin, tmax), max(tmin, tmax));
    return r;
}

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
