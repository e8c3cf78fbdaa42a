/*{
    "DESCRIPTION": "a persistent buffer counting frames: each frame adds `step` to what it held",
    "ISFVSN": "2.0",
    "INPUTS": [{"NAME": "step", "TYPE": "float", "DEFAULT": 0.0625, "MIN": 0.0, "MAX": 1.0}],
    "PASSES": [
        {"TARGET": "acc", "PERSISTENT": true, "FLOAT": true},
        {}
    ]
}*/
void main() {
    if (PASSINDEX == 0) gl_FragColor = IMG_THIS_PIXEL(acc) + vec4(step, step, step, 0.0);
    else gl_FragColor = vec4(IMG_THIS_PIXEL(acc).rgb, 1.0);
}
