/*{
    "DESCRIPTION": "an ISF file written for GLSL 1.x: varying from its .vs, texture2D, gl_FragColor",
    "ISFVSN": "2.0",
    "INPUTS": [{"NAME": "inputImage", "TYPE": "image"}]
}*/
#version 120
varying vec2 leftCoord;
void main() {
    // inverts the pixel one to the left (the .vs computes where that is)
    vec4 c = texture2D(inputImage, leftCoord);
    gl_FragColor = vec4(1.0 - c.rgb, 1.0);
}
