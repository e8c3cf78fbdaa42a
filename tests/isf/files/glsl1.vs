varying vec2 leftCoord;
void main() {
    isf_vertShaderInit();
    leftCoord = isf_FragNormCoord - vec2(1.0 / RENDERSIZE.x, 0.0);
}
