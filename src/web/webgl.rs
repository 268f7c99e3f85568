//! The WebGL2 renderer, for browsers without WebGPU: the same layer styles, shading, depth bias
//! and blending as the WebGPU renderer in [`super::gpu`], written directly on WebGL2. Going
//! through wgpu's WebGL backend instead would put its translation layer (wgpu-core, and naga
//! with its WGSL reader and GLSL writer) in the browser build: over a megabyte for two small
//! shaders.

use super::style::{BACKGROUND, LIGHT, Style};
use crate::app::camera::OrbitCamera;
use crate::app::geometry::{Geometry, Vertex};
use wasm_bindgen::{JsCast, JsValue};
use web_sys::{
    HtmlCanvasElement, WebGl2RenderingContext as Gl, WebGlBuffer, WebGlProgram, WebGlShader,
    WebGlUniformLocation, WebGlVertexArrayObject,
};

/// `shader.wgsl` in GLSL ES 3.0. The last line of `main` maps WebGPU's clip-space depth
/// (0..w) onto OpenGL's (−w..w), so both backends clip and order depth alike.
const VERTEX_SHADER: &str = "#version 300 es
uniform mat4 view_proj;
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec4 colour;
out vec3 v_normal;
out vec4 v_colour;
void main() {
    gl_Position = view_proj * vec4(position, 1.0);
    v_normal = normal;
    v_colour = colour;
    gl_Position.z = gl_Position.z * 2.0 - gl_Position.w;
}
";

const FRAGMENT_SHADER: &str = "#version 300 es
precision highp float;
uniform vec4 light;
in vec3 v_normal;
in vec4 v_colour;
out vec4 out_colour;
void main() {
    if (dot(v_normal, v_normal) < 0.25) {
        out_colour = v_colour;
        return;
    }
    float d = abs(dot(normalize(v_normal), normalize(light.xyz)));
    out_colour = vec4(v_colour.rgb * (0.35 + 0.65 * d), v_colour.a);
}
";

struct Layer {
    style: Style,
    vertex_array: Option<WebGlVertexArrayObject>,
    vertices: Option<WebGlBuffer>,
    indices: Option<WebGlBuffer>,
    count: i32,
}

/// A WebGL2 context on one canvas with its program and layers.
pub(super) struct GlRenderer {
    gl: Gl,
    program: WebGlProgram,
    view_proj: Option<WebGlUniformLocation>,
    light: Option<WebGlUniformLocation>,
    layers: Vec<Layer>,
    size: (u32, u32),
}

fn compile(gl: &Gl, kind: u32, source: &str) -> Result<WebGlShader, String> {
    let shader = gl
        .create_shader(kind)
        .ok_or("WebGL2: cannot create a shader")?;
    gl.shader_source(&shader, source);
    gl.compile_shader(&shader);
    if gl
        .get_shader_parameter(&shader, Gl::COMPILE_STATUS)
        .as_bool()
        .unwrap_or(false)
    {
        Ok(shader)
    } else {
        Err(format!(
            "WebGL2: the shader does not compile: {}",
            gl.get_shader_info_log(&shader).unwrap_or_default()
        ))
    }
}

fn link(gl: &Gl) -> Result<WebGlProgram, String> {
    let vertex = compile(gl, Gl::VERTEX_SHADER, VERTEX_SHADER)?;
    let fragment = compile(gl, Gl::FRAGMENT_SHADER, FRAGMENT_SHADER)?;
    let program = gl
        .create_program()
        .ok_or("WebGL2: cannot create a program")?;
    gl.attach_shader(&program, &vertex);
    gl.attach_shader(&program, &fragment);
    gl.link_program(&program);
    if gl
        .get_program_parameter(&program, Gl::LINK_STATUS)
        .as_bool()
        .unwrap_or(false)
    {
        Ok(program)
    } else {
        Err(format!(
            "WebGL2: the program does not link: {}",
            gl.get_program_info_log(&program).unwrap_or_default()
        ))
    }
}

impl GlRenderer {
    /// A WebGL2 context on `canvas`, without multisampling, like the WebGPU canvas. With
    /// `preserve`, the drawing stays readable after the frame (for [`GlRenderer::read_pixels`]).
    pub(super) fn new(canvas: &HtmlCanvasElement, preserve: bool) -> Result<Self, String> {
        let options = js_sys::Object::new();
        for (key, value) in [
            ("antialias", false),
            ("depth", true),
            ("preserveDrawingBuffer", preserve),
        ] {
            js_sys::Reflect::set(&options, &key.into(), &value.into())
                .map_err(|_| "WebGL2: cannot set the context options")?;
        }
        let gl: Gl = canvas
            .get_context_with_context_options("webgl2", &options)
            .ok()
            .flatten()
            .ok_or("the browser offers neither WebGPU nor WebGL2")?
            .dyn_into()
            .map_err(|_| "the canvas did not give a WebGL2 context")?;
        let program = link(&gl)?;
        let view_proj = gl.get_uniform_location(&program, "view_proj");
        let light = gl.get_uniform_location(&program, "light");
        Ok(Self {
            gl,
            program,
            view_proj,
            light,
            layers: Vec::new(),
            size: (canvas.width().max(1), canvas.height().max(1)),
        })
    }

    /// Sets the drawing size in device pixels (the canvas's own size is set by the caller).
    pub(super) fn resize(&mut self, width: u32, height: u32) {
        self.size = (width.max(1), height.max(1));
    }

    /// Replaces every layer (empty ones left out), freeing the old buffers.
    pub(super) fn set_layers(&mut self, layers: Vec<(Style, Geometry)>) {
        let gl = &self.gl;
        for old in self.layers.drain(..) {
            gl.delete_vertex_array(old.vertex_array.as_ref());
            gl.delete_buffer(old.vertices.as_ref());
            gl.delete_buffer(old.indices.as_ref());
        }
        let stride = std::mem::size_of::<Vertex>() as i32;
        for (style, g) in layers.into_iter().filter(|(_, g)| !g.indices.is_empty()) {
            let vertex_array = gl.create_vertex_array();
            gl.bind_vertex_array(vertex_array.as_ref());
            let vertices = gl.create_buffer();
            gl.bind_buffer(Gl::ARRAY_BUFFER, vertices.as_ref());
            gl.buffer_data_with_u8_array(
                Gl::ARRAY_BUFFER,
                bytemuck::cast_slice(&g.vertices),
                Gl::STATIC_DRAW,
            );
            // position, normal, colour: 3, 3 and 4 floats.
            for (location, size, offset) in [(0, 3, 0), (1, 3, 12), (2, 4, 24)] {
                gl.enable_vertex_attrib_array(location);
                gl.vertex_attrib_pointer_with_i32(location, size, Gl::FLOAT, false, stride, offset);
            }
            let indices = gl.create_buffer();
            gl.bind_buffer(Gl::ELEMENT_ARRAY_BUFFER, indices.as_ref());
            gl.buffer_data_with_u8_array(
                Gl::ELEMENT_ARRAY_BUFFER,
                bytemuck::cast_slice(&g.indices),
                Gl::STATIC_DRAW,
            );
            gl.bind_vertex_array(None);
            self.layers.push(Layer {
                style,
                vertex_array,
                vertices,
                indices,
                count: g.indices.len() as i32,
            });
        }
    }

    /// Draws the layers from `camera`: opaque fill pushed back by a depth bias (so the
    /// wireframe shows), then lines, then translucent fill without depth writes.
    pub(super) fn draw(&mut self, camera: &OrbitCamera) {
        let gl = &self.gl;
        let (width, height) = self.size;
        gl.viewport(0, 0, width as i32, height as i32);
        gl.clear_color(
            BACKGROUND.r as f32,
            BACKGROUND.g as f32,
            BACKGROUND.b as f32,
            BACKGROUND.a as f32,
        );
        gl.clear_depth(1.0);
        gl.depth_mask(true);
        gl.clear(Gl::COLOR_BUFFER_BIT | Gl::DEPTH_BUFFER_BIT);
        gl.use_program(Some(&self.program));
        let vp = camera.view_projection(width as f32 / height as f32);
        gl.uniform_matrix4fv_with_f32_array(self.view_proj.as_ref(), false, &vp.to_cols_array());
        gl.uniform4f(self.light.as_ref(), LIGHT[0], LIGHT[1], LIGHT[2], 0.0);
        gl.enable(Gl::DEPTH_TEST);
        gl.depth_func(Gl::LEQUAL);
        // The WebGPU pipelines' depth bias: constant 2, slope scale 1.
        gl.polygon_offset(1.0, 2.0);
        for style in [Style::Fill, Style::Lines, Style::Translucent] {
            let (mode, bias, blend) = match style {
                Style::Fill => (Gl::TRIANGLES, true, false),
                Style::Lines => (Gl::LINES, false, false),
                Style::Translucent => (Gl::TRIANGLES, true, true),
            };
            let toggle = |cap, on| {
                if on { gl.enable(cap) } else { gl.disable(cap) }
            };
            toggle(Gl::POLYGON_OFFSET_FILL, bias);
            toggle(Gl::BLEND, blend);
            gl.depth_mask(!blend);
            if blend {
                gl.blend_func_separate(
                    Gl::SRC_ALPHA,
                    Gl::ONE_MINUS_SRC_ALPHA,
                    Gl::ONE,
                    Gl::ONE_MINUS_SRC_ALPHA,
                );
            }
            for layer in self.layers.iter().filter(|l| l.style == style) {
                gl.bind_vertex_array(layer.vertex_array.as_ref());
                gl.draw_elements_with_i32(mode, layer.count, Gl::UNSIGNED_INT, 0);
            }
        }
        gl.bind_vertex_array(None);
        gl.depth_mask(true);
    }

    /// The drawn pixels as RGBA8, row by row from the top (WebGL reads from the bottom).
    pub(super) fn read_pixels(&self) -> Result<Vec<u8>, String> {
        let (width, height) = self.size;
        let row = 4 * width as usize;
        let mut bottom_up = vec![0u8; row * height as usize];
        self.gl
            .read_pixels_with_opt_u8_array(
                0,
                0,
                width as i32,
                height as i32,
                Gl::RGBA,
                Gl::UNSIGNED_BYTE,
                Some(&mut bottom_up),
            )
            .map_err(|e: JsValue| format!("WebGL2: cannot read the pixels: {e:?}"))?;
        Ok(bottom_up
            .chunks_exact(row)
            .rev()
            .flatten()
            .copied()
            .collect())
    }
}
