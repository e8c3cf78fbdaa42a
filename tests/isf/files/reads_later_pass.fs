/*{
    "DESCRIPTION": "a pass that reads a later pass's target (its last frame), as feedback chains do",
    "ISFVSN": "2.0",
    "PASSES": [
        {"TARGET": "first", "WIDTH": "$WIDTH / 2", "HEIGHT": "$HEIGHT / 2"},
        {"TARGET": "second", "WIDTH": "$WIDTH / 4", "HEIGHT": "$HEIGHT / 4"},
        {}
    ]
}*/
// Pass 0 writes the size of the texture bound as `second` (made by pass 1) into `first`; the
// last pass shows it, divided by 255.
void main() {
    if (PASSINDEX == 0) gl_FragColor = vec4(vec2(textureSize(second, 0)) / 255.0, 0.0, 1.0);
    else if (PASSINDEX == 1) gl_FragColor = vec4(0.5);
    else gl_FragColor = IMG_NORM_PIXEL(first, isf_FragNormCoord);
}
