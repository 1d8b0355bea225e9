// The page's side of the generated fragment shader: where the painting lies in the
// framebuffer and how its result is shown.

uniform vec4 dp_rect;        // the painting's rectangle in framebuffer pixels: x, y, width, height
uniform int dp_display;      // 1: over the backdrop, sRGB-encoded; 0: premultiplied linear RGBA
uniform vec3 dp_backdrop;    // the page colour behind a transparent painting (linear)
out vec4 dp_fragment;

// The painting's UV, (u, v) ∈ [0, 1]² over its rectangle, v up (gl_FragCoord's y is up too).
#define dp_uv() vec3((gl_FragCoord.xy - dp_rect.xy) / dp_rect.zw, 0.0)

vec3 dp_linear_to_srgb(vec3 c)
{
    c = clamp(c, 0.0, 1.0);
    vec3 hi = 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055;
    return mix(hi, c * 12.92, vec3(lessThanEqual(c, vec3(0.0031308))));
}

void dp_show(vec3 rgb, float alpha)
{
    if (dp_display == 0) {
        dp_fragment = vec4(rgb, alpha);
    } else {
        dp_fragment = vec4(dp_linear_to_srgb(rgb + dp_backdrop * (1.0 - clamp(alpha, 0.0, 1.0))), 1.0);
    }
}

