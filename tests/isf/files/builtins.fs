/*{
    "DESCRIPTION": "the ISF built-ins, each drawn as a colour",
    "ISFVSN": "2.0"
}*/
// Left half: TIME/10, FRAMEINDEX/255, TIMEDELTA*10. Right half: isf_FragNormCoord and whether
// RENDERSIZE, DATE and PASSINDEX hold what the host set (1 = yes).
void main() {
    if (isf_FragNormCoord.x < 0.5) {
        gl_FragColor = vec4(TIME / 10.0, float(FRAMEINDEX) / 255.0, TIMEDELTA * 10.0, 1.0);
    } else {
        bool sizeOk = RENDERSIZE == vec2(64.0, 32.0) && abs(gl_FragCoord.x / RENDERSIZE.x - isf_FragNormCoord.x) < 1e-4;
        bool dateOk = DATE == vec4(2024.0, 1.0, 1.0, 0.0) && PASSINDEX == 0;
        gl_FragColor = vec4(isf_FragNormCoord.y, sizeOk ? 1.0 : 0.0, dateOk ? 1.0 : 0.0, 1.0);
    }
}
