// The words the shader sources shared with OSL (shared/dp_nodes.h, cos_theta.h) are
// written in, as GLSL ES 3.00 says them.
#define vector vec3
#define fabs abs
#define output out
#define DP_IMAGE sampler2D

float hypot(float a, float b) { return length(vec2(a, b)); }

