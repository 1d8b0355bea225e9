// Blender's node semantics in OSL, so generated code computes what the node trees compute
// (blender-notes.md: division by zero gives 0, Map Range at From Min = From Max gives To Min,
// normalizing (0, 0, 0) gives (0, 0, 0)), and the painting's texture lookups.

float dp_div(float a, float b) { return b != 0.0 ? a / b : 0.0; }
vector dp_vdiv(vector a, vector b)
{
    return vector(dp_div(a[0], b[0]), dp_div(a[1], b[1]), dp_div(a[2], b[2]));
}
float dp_sqrt(float a) { return a > 0.0 ? sqrt(a) : 0.0; }
float dp_abs(float a) { return fabs(a); }
float dp_sign(float a) { return a > 0.0 ? 1.0 : (a < 0.0 ? -1.0 : 0.0); }
float dp_pow(float a, float b)
{
    if (a >= 0.0) return pow(a, b);
    float f = b - floor(b);          // negative base: integer exponents only (Blender's rule)
    return (f > 0.999 || f < 0.001) ? pow(a, floor(b + 0.5)) : 0.0;
}
float dp_compare(float a, float b, float eps) { return fabs(a - b) <= max(eps, 1.1920929e-7) ? 1.0 : 0.0; }
vector dp_normalize(vector a) { float l = length(a); return l > 0.0 ? a / l : vector(0.0); }
float dp_mix(float a, float b, float t) { return a * (1.0 - t) + b * t; }
vector dp_vmix(vector a, vector b, vector t) { return a * (vector(1.0) - t) + b * t; }

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
    if (clamp_ && interp == 0) r = clamp(r, min(tmin, tmax), max(tmin, tmax));
    return r;
}

float dp_srgb_to_linear(float c)
{
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

// The painting's UV, (u, v) ∈ [0, 1]² over the plane, v up: the shader's `painting_uv` input,
// linked to a Texture Coordinate node's UV (Cycles exports attributes a Script node reads
// by a computed name only if asked, so the UV comes in as a socket).
#define dp_uv() painting_uv

// An image at a UV with no mip filtering ("width" 0): OIIO's t runs down the image.
vector dp_tex(string file, int srgb, vector uv, string wrap, string interp, output float a)
{
    a = 1.0;
    color c = texture(file, uv[0], 1.0 - uv[1], "wrap", wrap, "interp", interp, "width", 0.0,
                      "alpha", a, "fill", 1.0);
    if (srgb)
        c = color(dp_srgb_to_linear(c[0]), dp_srgb_to_linear(c[1]), dp_srgb_to_linear(c[2]));
    return vector(c);
}
