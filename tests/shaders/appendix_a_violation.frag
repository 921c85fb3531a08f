#version 100
// Negative control for tests/validate_shaders.sh: a loop bound read from a
// uniform breaks GLSL ES 1.00 Appendix A (section 4: the condition must
// compare the loop index with a constant expression). Mesa and glslang's
// default limits accept it; the strict limits config must reject it.
precision mediump float;
uniform mediump int u_count;
void main() {
    mediump float sum = 0.0;
    for (int i = 0; i < u_count; i++) {
        sum += 0.1;
    }
    gl_FragColor = vec4(sum);
}
