/*{
    "DESCRIPTION": "an IMPORTED image shown as it is (the test writes logo.png beside a copy of this file)",
    "ISFVSN": "2.0",
    "IMPORTED": {"logo": {"PATH": "logo.png"}}
}*/
void main() {
    gl_FragColor = IMG_NORM_PIXEL(logo, isf_FragNormCoord);
}
