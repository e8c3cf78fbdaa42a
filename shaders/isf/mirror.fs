/*{
    "DESCRIPTION": "Mirror: one half of the frame reflected onto the other (sdfvj post effect)",
    "CREDIT": "sdfvj",
    "ISFVSN": "2",
    "CATEGORIES": ["Geometry Adjustment"],
    "INPUTS": [
        {"NAME": "inputImage", "TYPE": "image"},
        {"NAME": "mode", "TYPE": "long", "VALUES": [0, 1, 2, 3], "LABELS": ["left onto right", "right onto left", "bottom onto top", "top onto bottom"], "DEFAULT": 0, "LABEL": "Mode"}
    ]
}*/
// Mirror: keeps one half and shows its reflection in the other half. The mirror line is the
// centre of the frame; x = 0.5 maps onto itself.
void main() {
    vec2 uv = isf_FragNormCoord;
    if (mode == 0) uv.x = uv.x > 0.5 ? 1.0 - uv.x : uv.x;
    else if (mode == 1) uv.x = uv.x < 0.5 ? 1.0 - uv.x : uv.x;
    else if (mode == 2) uv.y = uv.y > 0.5 ? 1.0 - uv.y : uv.y;
    else uv.y = uv.y < 0.5 ? 1.0 - uv.y : uv.y;
    gl_FragColor = IMG_NORM_PIXEL(inputImage, uv);
}
