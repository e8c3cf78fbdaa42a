/*{
    "ISFVSN": "2",
    "DESCRIPTION": "sdfvj's tempo in an ISF file: red is u_beat (the beat phase), green u_bpm / 240",
    "CATEGORIES": ["Test"],
    "INPUTS": []
}*/
void main() {
    gl_FragColor = vec4(u_beat, u_bpm / 240.0, 0.0, 1.0);
}
