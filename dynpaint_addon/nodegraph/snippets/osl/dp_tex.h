// The OSL shader's image lookups: files read by OIIO, and the painting's UV.

#define DP_IMAGE string

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
    if (srgb != 0)
        c = color(dp_srgb_to_linear(c[0]), dp_srgb_to_linear(c[1]), dp_srgb_to_linear(c[2]));
    return vector(c);
}

// An image at (u, v), linear between texel centres, edges extended: what the march reads.
vector dp_image_at(string file, int srgb, float u, float v)
{
    float a;
    return dp_tex(file, srgb, vector(u, v, 0.0), "clamp", "linear", a);
}
