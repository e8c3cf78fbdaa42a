/*{
    "DESCRIPTION": "a pass into a target an eighth of the size, read back by the next pass",
    "ISFVSN": "2.0",
    "INPUTS": [{"NAME": "divisor", "TYPE": "float", "DEFAULT": 8.0, "MIN": 1.0, "MAX": 16.0}],
    "PASSES": [
        {"TARGET": "small", "WIDTH": "$WIDTH / $divisor", "HEIGHT": "floor($HEIGHT / $divisor)"},
        {}
    ]
}*/
// Pass 0 writes its RENDERSIZE (the target's size) into `small`; pass 1 shows it next to
// IMG_SIZE(small) and its own RENDERSIZE, all divided by 255.
void main() {
    if (PASSINDEX == 0) gl_FragColor = vec4(RENDERSIZE / 255.0, 0.0, 1.0);
    else gl_FragColor = vec4(IMG_THIS_PIXEL(small).rg, IMG_SIZE(small).x / 255.0, RENDERSIZE.x / 255.0);
}
