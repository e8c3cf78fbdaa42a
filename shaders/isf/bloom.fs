/*{
    "DESCRIPTION": "Bloom: what is brighter than a threshold glows into its surroundings (sdfvj post effect)",
    "CREDIT": "sdfvj",
    "ISFVSN": "2",
    "CATEGORIES": ["Stylize", "Glow"],
    "INPUTS": [
        {"NAME": "inputImage", "TYPE": "image"},
        {"NAME": "threshold", "TYPE": "float", "DEFAULT": 0.85, "MIN": 0.0, "MAX": 1.0, "LABEL": "Threshold"},
        {"NAME": "intensity", "TYPE": "float", "DEFAULT": 0.8, "MIN": 0.0, "MAX": 4.0, "LABEL": "Intensity"},
        {"NAME": "radius", "TYPE": "float", "DEFAULT": 4.0, "MIN": 1.0, "MAX": 16.0, "LABEL": "Radius (quarter pixels)"}
    ],
    "PASSES": [
        {"TARGET": "bright", "WIDTH": "max(floor($WIDTH / 4.0), 1.0)", "HEIGHT": "max(floor($HEIGHT / 4.0), 1.0)", "FLOAT": true},
        {"TARGET": "blurX", "WIDTH": "max(floor($WIDTH / 4.0), 1.0)", "HEIGHT": "max(floor($HEIGHT / 4.0), 1.0)", "FLOAT": true},
        {"TARGET": "blurY", "WIDTH": "max(floor($WIDTH / 4.0), 1.0)", "HEIGHT": "max(floor($HEIGHT / 4.0), 1.0)", "FLOAT": true},
        {}
    ]
}*/
// Bloom in four passes: (0) keep what is above threshold at a quarter of the size, (1, 2) a
// separable Gaussian blur of sigma = radius/2 quarter-size pixels, (3) add it to the frame.
// Below the threshold nothing changes: an image without highlights comes out as it went in.
vec3 blur(sampler2D img, vec2 dir) {
    vec2 texel = 1.0 / IMG_SIZE(img);
    float sigma = max(radius * 0.5, 0.5);
    vec3 sum = vec3(0.0);
    float total = 0.0;
    for (int i = -16; i <= 16; ++i) {
        float w = exp(-0.5 * float(i * i) / (sigma * sigma));
        sum += w * IMG_NORM_PIXEL(img, isf_FragNormCoord + dir * texel * float(i)).rgb;
        total += w;
    }
    return sum / total;
}
void main() {
    if (PASSINDEX == 0) {
        vec3 c = IMG_NORM_PIXEL(inputImage, isf_FragNormCoord).rgb;
        float luma = dot(c, vec3(0.2126, 0.7152, 0.0722));
        gl_FragColor = vec4(c * step(threshold, luma) * max(luma - threshold, 0.0) / max(1.0 - threshold, 1e-3), 1.0);
    } else if (PASSINDEX == 1) {
        gl_FragColor = vec4(blur(bright, vec2(1.0, 0.0)), 1.0);
    } else if (PASSINDEX == 2) {
        gl_FragColor = vec4(blur(blurX, vec2(0.0, 1.0)), 1.0);
    } else {
        vec4 src = IMG_THIS_PIXEL(inputImage);
        gl_FragColor = vec4(clamp(src.rgb + intensity * IMG_THIS_NORM_PIXEL(blurY).rgb, 0.0, 1.0), src.a);
    }
}
