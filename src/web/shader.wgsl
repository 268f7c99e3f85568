// Shaded or unlit geometry: a zero normal draws the vertex colour unlit (lines, markers).
struct Uniforms {
    view_proj: mat4x4<f32>,
    light: vec4<f32>,
};
@group(0) @binding(0) var<uniform> u: Uniforms;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) colour: vec4<f32>,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
    @location(1) colour: vec4<f32>,
};

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    var out: VertexOut;
    out.clip = u.view_proj * vec4<f32>(v.position, 1.0);
    out.normal = v.normal;
    out.colour = v.colour;
    return out;
}

@fragment
fn fs_main(v: VertexOut) -> @location(0) vec4<f32> {
    if (dot(v.normal, v.normal) < 0.25) {
        return v.colour;
    }
    // Two-sided Lambert with ambient, so both faces of an open surface read well.
    let d = abs(dot(normalize(v.normal), normalize(u.light.xyz)));
    return vec4<f32>(v.colour.rgb * (0.35 + 0.65 * d), v.colour.a);
}
