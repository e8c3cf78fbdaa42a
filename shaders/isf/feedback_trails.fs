/*{
    "DESCRIPTION": "Feedback trails: each frame is laid over the last one, which fades (sdfvj post effect)",
    "CREDIT": "sdfvj",
    "ISFVSN": "2",
    "CATEGORIES": ["Stylize"],
    "INPUTS": [
        {"NAME": "inputImage", "TYPE": "image"},
        {"NAME": "decay", "TYPE": "float", "DEFAULT": 0.9, "MIN": 0.0, "MAX": 0.995, "LABEL": "Trail length"},
        {"NAME": "zoom", "TYPE": "float", "DEFAULT": 1.0, "MIN": 0.9, "MAX": 1.1, "LABEL": "Trail zoom"}
    ],
    "PASSES": [
        {"TARGET": "trails", "PERSISTENT": true, "FLOAT": true},
        {}
    ]
}*/
// Feedback trails: a persistent float buffer holds max(frame, decay * previous trails) (the
// previous trails optionally zoomed about the centre); the output shows it. A lit pixel that
// goes dark fades as decay^frames.
void main() {
    if (PASSINDEX == 0) {
        vec2 uv = (isf_FragNormCoord - 0.5) / zoom + 0.5;
        vec4 previous = IMG_NORM_PIXEL(trails, uv) * decay;
        vec4 now = IMG_THIS_PIXEL(inputImage);
        gl_FragColor = max(now, previous);
    } else {
        gl_FragColor = IMG_THIS_PIXEL(trails);
    }
}
