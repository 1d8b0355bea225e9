// Blender's node semantics, so generated code computes what the node trees compute
// (blender-notes.md: division by zero gives 0, Map Range at From Min = From Max gives To Min,
// normalizing (0, 0, 0) gives (0, 0, 0)).
//
// Shared by the OSL shader and the web page's GLSL (nodegraph/text_codegen.py): written in
// the words both languages read; the GLSL prelude (glsl/dp_words.glsl) maps
// `vector`, `fabs` and `output` to GLSL's. Conditions compare ints explicitly (GLSL has no
// int truth), casts are constructor calls (`int(x)`), both languages' form.

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
    if (a > 0.0) return pow(a, b);
    if (a == 0.0) return b > 0.0 ? 0.0 : (b == 0.0 ? 1.0 : 0.0);
    float f = b - floor(b);          // negative base: integer exponents only (Blender's rule)
    if (f > 0.001 && f < 0.999) return 0.0;
    float e = floor(b + 0.5);
    float r = pow(-a, e);            // pow of a negative base is undefined in GLSL
    return e - 2.0 * floor(e / 2.0) == 1.0 ? -r : r;
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
    if (clamp_ != 0 && interp == 0) r = clamp(r, min(tmin, tmax), max(tmin, tmax));
    return r;
}
