/*{
    "DESCRIPTION": "a compile error on line 9 of this file",
    "ISFVSN": "2.0"
}*/
// the error below must be reported as syntax_error.fs:9

void main() {
    vec4 c = vec4(1.0);
    gl_FragColor = c * undeclaredThing;
}
