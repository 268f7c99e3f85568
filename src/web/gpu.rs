//! The 3-D view's renderer: WebGPU through wgpu where the browser offers an adapter, else
//! WebGL2 ([`super::webgl`]). It draws named layers of [`Geometry`] each frame in three styles:
//! shaded fill (pushed back by a depth bias so the wireframe shows), lines, and translucent fill.

use super::style::{BACKGROUND, LIGHT, Style};
use super::webgl::GlRenderer;
use crate::app::camera::OrbitCamera;
use crate::app::geometry::{Geometry, Vertex};
use web_sys::HtmlCanvasElement;
use wgpu::util::DeviceExt;

struct Layer {
    style: Style,
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    count: u32,
}

/// The renderer on one canvas.
pub(super) struct Renderer {
    view: View,
    /// "WebGPU" or "WebGL2".
    pub backend: &'static str,
}

enum View {
    WebGpu(Box<WebGpuView>),
    WebGl2(GlRenderer),
}

/// The WebGPU state for one canvas.
struct WebGpuView {
    surface: wgpu::Surface<'static>,
    device: wgpu::Device,
    queue: wgpu::Queue,
    config: wgpu::SurfaceConfiguration,
    depth: wgpu::TextureView,
    pipelines: Pipelines,
    layers: Vec<Layer>,
}

const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth24Plus;

fn depth_view(device: &wgpu::Device, width: u32, height: u32) -> wgpu::TextureView {
    device
        .create_texture(&wgpu::TextureDescriptor {
            label: Some("depth"),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: DEPTH_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        })
        .create_view(&wgpu::TextureViewDescriptor::default())
}

/// The three pipelines and their uniforms, for one colour target format.
struct Pipelines {
    uniforms: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    fill: wgpu::RenderPipeline,
    lines: wgpu::RenderPipeline,
    translucent: wgpu::RenderPipeline,
}

/// A WebGPU device on `canvas`, with the surface, adapter and queue. `fail_device` asks for
/// more bind groups than the adapter has, so that the browser refuses the device: how the
/// end-to-end test reaches the WebGL2 fallback on a browser whose WebGPU works.
async fn open(canvas: HtmlCanvasElement, fail_device: bool) -> Result<Opened, String> {
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
    desc.backends = wgpu::Backends::BROWSER_WEBGPU;
    let instance = wgpu::Instance::new(desc);
    let surface = instance
        .create_surface(wgpu::SurfaceTarget::Canvas(canvas))
        .map_err(|e| format!("cannot draw on the canvas: {e}"))?;
    let adapter = instance
        .request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::default(),
            force_fallback_adapter: false,
            compatible_surface: Some(&surface),
            apply_limit_buckets: false,
        })
        .await
        .map_err(|e| format!("no WebGPU adapter: {e}"))?;
    let mut required_limits =
        wgpu::Limits::downlevel_webgl2_defaults().using_resolution(adapter.limits());
    if fail_device {
        required_limits.max_bind_groups = adapter.limits().max_bind_groups.saturating_add(1);
    }
    let (device, queue) = adapter
        .request_device(&wgpu::DeviceDescriptor {
            label: Some("paretomesh"),
            required_features: wgpu::Features::empty(),
            required_limits,
            ..Default::default()
        })
        .await
        .map_err(|e| format!("cannot open the GPU device: {e}"))?;
    Ok(Opened {
        surface,
        adapter,
        device,
        queue,
    })
}

struct Opened {
    surface: wgpu::Surface<'static>,
    adapter: wgpu::Adapter,
    device: wgpu::Device,
    queue: wgpu::Queue,
}

/// True when the browser offers a WebGPU adapter. Asked before a canvas gets a context: a
/// canvas that gave a WebGPU context cannot give a WebGL2 one.
async fn webgpu_available() -> bool {
    wgpu::util::is_browser_webgpu_supported().await
}

impl Pipelines {
    fn new(device: &wgpu::Device, format: wgpu::TextureFormat) -> Self {
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("shader"),
            source: wgpu::ShaderSource::Wgsl(include_str!("shader.wgsl").into()),
        });
        let uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("uniforms"),
            size: 80,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bind_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("uniforms"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("uniforms"),
            layout: &bind_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: uniforms.as_entire_binding(),
            }],
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("layout"),
            bind_group_layouts: &[Some(&bind_layout)],
            immediate_size: 0,
        });
        let attributes = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x4];
        let make = |topology, depth_write, bias, blend| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("pipeline"),
                layout: Some(&layout),
                vertex: wgpu::VertexState {
                    module: &shader,
                    entry_point: Some("vs_main"),
                    compilation_options: Default::default(),
                    buffers: &[Some(wgpu::VertexBufferLayout {
                        array_stride: std::mem::size_of::<Vertex>() as u64,
                        step_mode: wgpu::VertexStepMode::Vertex,
                        attributes: &attributes,
                    })],
                },
                primitive: wgpu::PrimitiveState {
                    topology,
                    ..Default::default()
                },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH_FORMAT,
                    depth_write_enabled: Some(depth_write),
                    depth_compare: Some(wgpu::CompareFunction::LessEqual),
                    stencil: Default::default(),
                    bias,
                }),
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &shader,
                    entry_point: Some("fs_main"),
                    compilation_options: Default::default(),
                    targets: &[Some(wgpu::ColorTargetState {
                        format,
                        blend,
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let pushed_back = wgpu::DepthBiasState {
            constant: 2,
            slope_scale: 1.0,
            clamp: 0.0,
        };
        Self {
            fill: make(
                wgpu::PrimitiveTopology::TriangleList,
                true,
                pushed_back,
                None,
            ),
            lines: make(
                wgpu::PrimitiveTopology::LineList,
                true,
                Default::default(),
                None,
            ),
            translucent: make(
                wgpu::PrimitiveTopology::TriangleList,
                false,
                pushed_back,
                Some(wgpu::BlendState::ALPHA_BLENDING),
            ),
            uniforms,
            bind_group,
        }
    }

    /// Encodes one frame of `layers` seen from `camera` into `target` (with `depth`, both
    /// `width` × `height`).
    #[allow(clippy::too_many_arguments)]
    fn encode(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        target: &wgpu::TextureView,
        depth: &wgpu::TextureView,
        (width, height): (u32, u32),
        camera: &OrbitCamera,
        layers: &[Layer],
    ) {
        let aspect = width as f32 / height as f32;
        let vp = camera.view_projection(aspect);
        let mut data = [0f32; 20];
        data[..16].copy_from_slice(&vp.to_cols_array());
        data[16..19].copy_from_slice(&LIGHT);
        queue.write_buffer(&self.uniforms, 0, bytemuck::cast_slice(&data));
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("scene"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: target,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(BACKGROUND),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            ..Default::default()
        });
        pass.set_bind_group(0, &self.bind_group, &[]);
        for style in [Style::Fill, Style::Lines, Style::Translucent] {
            pass.set_pipeline(match style {
                Style::Fill => &self.fill,
                Style::Lines => &self.lines,
                Style::Translucent => &self.translucent,
            });
            for layer in layers.iter().filter(|l| l.style == style) {
                pass.set_vertex_buffer(0, layer.vertices.slice(..));
                pass.set_index_buffer(layer.indices.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..layer.count, 0, 0..1);
            }
        }
    }
}

/// Resolves after `ms` milliseconds on the page's timer, letting the browser run callbacks.
async fn sleep_ms(ms: i32) {
    let promise = js_sys::Promise::new(&mut |resolve, _| {
        if let Some(w) = web_sys::window() {
            let _ = w.set_timeout_with_callback_and_timeout_and_arguments_0(&resolve, ms);
        }
    });
    let _ = wasm_bindgen_futures::JsFuture::from(promise).await;
}

/// GPU buffers of `layers` (empty ones left out).
fn upload(device: &wgpu::Device, layers: Vec<(Style, Geometry)>) -> Vec<Layer> {
    layers
        .into_iter()
        .filter(|(_, g)| !g.indices.is_empty())
        .map(|(style, g)| Layer {
            style,
            vertices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("vertices"),
                contents: bytemuck::cast_slice(&g.vertices),
                usage: wgpu::BufferUsages::VERTEX,
            }),
            indices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("indices"),
                contents: bytemuck::cast_slice(&g.indices),
                usage: wgpu::BufferUsages::INDEX,
            }),
            count: g.indices.len() as u32,
        })
        .collect()
}

/// Draws `layers` from `camera` into an offscreen `width` × `height` RGBA8 image and reads it
/// back: the pixels, row by row from the top, 4 bytes each. `backend` is "webgpu" or "webgl2";
/// returns the backend's name with the pixels. A canvas presents nothing in a headless browser
/// under WebGPU, but a texture read back does, so this is how a test sees what the WebGPU path
/// draws.
pub(super) async fn render_offscreen(
    backend: &str,
    (width, height): (u32, u32),
    camera: &OrbitCamera,
    layers: Vec<(Style, Geometry)>,
) -> Result<(&'static str, Vec<u8>), String> {
    let canvas: HtmlCanvasElement = web_sys::window()
        .and_then(|w| w.document())
        .and_then(|d| d.create_element("canvas").ok())
        .and_then(|e| wasm_bindgen::JsCast::dyn_into(e).ok())
        .ok_or("cannot create a canvas")?;
    canvas.set_width(width);
    canvas.set_height(height);
    match backend {
        "webgpu" => Ok((
            "WebGPU",
            webgpu_offscreen(canvas, (width, height), camera, layers).await?,
        )),
        "webgl2" => {
            let mut gl = GlRenderer::new(&canvas, true)?;
            gl.set_layers(layers);
            gl.draw(camera);
            Ok(("WebGL2", gl.read_pixels()?))
        }
        other => Err(format!("unknown backend “{other}”: webgpu or webgl2")),
    }
}

/// [`render_offscreen`] on WebGPU: a texture, `copy_texture_to_buffer`, then a mapped buffer.
async fn webgpu_offscreen(
    canvas: HtmlCanvasElement,
    (width, height): (u32, u32),
    camera: &OrbitCamera,
    layers: Vec<(Style, Geometry)>,
) -> Result<Vec<u8>, String> {
    let gpu = open(canvas, false).await?;
    let (device, queue) = (&gpu.device, &gpu.queue);
    let format = wgpu::TextureFormat::Rgba8Unorm;
    let size = wgpu::Extent3d {
        width,
        height,
        depth_or_array_layers: 1,
    };
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("offscreen"),
        size,
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let pipelines = Pipelines::new(device, format);
    let layers = upload(device, layers);
    let depth = depth_view(device, width, height);
    let row = (4 * width).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
        * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let readback = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: u64::from(row) * u64::from(height),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("offscreen"),
    });
    let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
    pipelines.encode(
        queue,
        &mut encoder,
        &view,
        &depth,
        (width, height),
        camera,
        &layers,
    );
    encoder.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture: &texture,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &readback,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(row),
                rows_per_image: Some(height),
            },
        },
        size,
    );
    queue.submit([encoder.finish()]);
    // WebGPU calls back from the browser's event loop: yield to it until the buffer is mapped.
    let mapped = std::rc::Rc::new(std::cell::Cell::new(None));
    let done = mapped.clone();
    readback
        .slice(..)
        .map_async(wgpu::MapMode::Read, move |r| done.set(Some(r.is_ok())));
    let mut waits = 0;
    let ok = loop {
        let _ = device.poll(wgpu::PollType::Poll);
        if let Some(ok) = mapped.get() {
            break ok;
        }
        waits += 1;
        if waits > 2000 {
            return Err("the GPU did not return the pixels within 10 s".to_string());
        }
        sleep_ms(5).await;
    };
    if !ok {
        return Err("the readback buffer could not be mapped".to_string());
    }
    let data = readback
        .slice(..)
        .get_mapped_range()
        .map_err(|e| format!("cannot read the mapped buffer: {e}"))?;
    let mut pixels = Vec::with_capacity((4 * width * height) as usize);
    for y in 0..height as usize {
        let at = y * row as usize;
        pixels.extend_from_slice(&data[at..at + 4 * width as usize]);
    }
    drop(data);
    readback.unmap();
    Ok(pixels)
}

/// Which backend the 3-D view tries.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum BackendChoice {
    /// WebGPU when the browser offers an adapter, else WebGL2.
    Auto,
    /// WebGL2 only (headless screenshots need it: a WebGPU canvas stays blank there).
    WebGl2,
    /// WebGPU with a device request the browser must refuse, to exercise the fallback.
    FailingWebGpu,
}

impl Renderer {
    /// Sets up the view on `canvas`: WebGPU as `choice` says, else WebGL2. When
    /// WebGPU is offered but its device, canvas configuration or pipelines cannot be set up,
    /// the console says why and the view falls back to WebGL2 on a copy of the canvas that
    /// replaces it in the page (a canvas that gave a WebGPU context gives no WebGL2 one), so
    /// callers must look the canvas up again after this.
    pub(super) async fn new(
        canvas: HtmlCanvasElement,
        choice: BackendChoice,
    ) -> Result<Self, String> {
        let mut canvas = canvas;
        if choice != BackendChoice::WebGl2 && webgpu_available().await {
            let fail_device = choice == BackendChoice::FailingWebGpu;
            match WebGpuView::new(canvas.clone(), fail_device).await {
                Ok(view) => {
                    return Ok(Self {
                        view: View::WebGpu(Box::new(view)),
                        backend: "WebGPU",
                    });
                }
                Err(e) => {
                    web_sys::console::warn_1(
                        &format!(
                            "ParetoMesh: WebGPU offers an adapter but cannot draw ({e}); \
                             falling back to WebGL2"
                        )
                        .into(),
                    );
                    canvas = fresh_canvas(&canvas)?;
                }
            }
        }
        Ok(Self {
            view: View::WebGl2(GlRenderer::new(&canvas, false)?),
            backend: "WebGL2",
        })
    }

    /// Resizes the drawing buffer to `width` × `height` device pixels when it changed.
    pub(super) fn resize(&mut self, width: u32, height: u32) {
        match &mut self.view {
            View::WebGpu(v) => v.resize(width, height),
            View::WebGl2(v) => v.resize(width, height),
        }
    }

    /// Replaces every layer.
    pub(super) fn set_layers(&mut self, layers: Vec<(Style, Geometry)>) {
        match &mut self.view {
            View::WebGpu(v) => v.layers = upload(&v.device, layers),
            View::WebGl2(v) => v.set_layers(layers),
        }
    }

    /// Draws the layers from `camera`.
    pub(super) fn draw(&mut self, camera: &OrbitCamera) {
        match &mut self.view {
            View::WebGpu(v) => v.draw(camera),
            View::WebGl2(v) => v.draw(camera),
        }
    }
}

/// A copy of `canvas` (same id, classes, size) put in its place in the page, without its
/// context, so that it can give a WebGL2 context after the original gave a WebGPU one.
fn fresh_canvas(canvas: &HtmlCanvasElement) -> Result<HtmlCanvasElement, String> {
    let copy: HtmlCanvasElement = canvas
        .clone_node()
        .ok()
        .and_then(|node| wasm_bindgen::JsCast::dyn_into(node).ok())
        .ok_or("cannot copy the canvas for the WebGL2 fallback")?;
    canvas
        .replace_with_with_node_1(&copy)
        .map_err(|_| "cannot put a fresh canvas in the page for the WebGL2 fallback")?;
    Ok(copy)
}

impl WebGpuView {
    /// The WebGPU view on `canvas`, checked by acquiring its first frame: a refused device, a
    /// canvas configuration the browser rejects, or a pipeline that does not validate is an
    /// error here rather than a blank or panicking view later.
    async fn new(canvas: HtmlCanvasElement, fail_device: bool) -> Result<Self, String> {
        let (width, height) = (canvas.width().max(1), canvas.height().max(1));
        let Opened {
            surface,
            adapter,
            device,
            queue,
        } = open(canvas, fail_device).await?;
        let mut config = surface
            .get_default_config(&adapter, width, height)
            .ok_or("the canvas surface is not supported by the adapter")?;
        config.present_mode = wgpu::PresentMode::Fifo;
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        surface.configure(&device, &config);
        let pipelines = Pipelines::new(&device, config.format);
        let depth = depth_view(&device, config.width, config.height);
        if let Some(e) = scope.pop().await {
            return Err(format!("cannot set up drawing on the canvas: {e}"));
        }
        let mut view = Self {
            surface,
            device,
            queue,
            config,
            depth,
            pipelines,
            layers: Vec::new(),
        };
        // The browser reports a rejected canvas configuration only as a lost surface.
        if !view.present(&OrbitCamera::default()) {
            return Err("the browser rejected the canvas configuration".to_string());
        }
        Ok(view)
    }

    fn resize(&mut self, width: u32, height: u32) {
        let (width, height) = (width.max(1), height.max(1));
        if (width, height) != (self.config.width, self.config.height) {
            self.config.width = width;
            self.config.height = height;
            self.surface.configure(&self.device, &self.config);
            self.depth = depth_view(&self.device, width, height);
        }
    }

    fn draw(&mut self, camera: &OrbitCamera) {
        if !self.present(camera) {
            self.surface.configure(&self.device, &self.config);
        }
    }

    /// Draws one frame; false when the surface is lost or outdated (nothing drawn).
    fn present(&mut self, camera: &OrbitCamera) -> bool {
        let frame = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(f)
            | wgpu::CurrentSurfaceTexture::Suboptimal(f) => f,
            wgpu::CurrentSurfaceTexture::Outdated
            | wgpu::CurrentSurfaceTexture::Lost
            | wgpu::CurrentSurfaceTexture::Validation => return false,
            _ => return true,
        };
        let view = frame
            .texture
            .create_view(&wgpu::TextureViewDescriptor::default());
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("frame"),
            });
        self.pipelines.encode(
            &self.queue,
            &mut encoder,
            &view,
            &self.depth,
            (self.config.width, self.config.height),
            camera,
            &self.layers,
        );
        self.queue.submit([encoder.finish()]);
        self.queue.present(frame);
        true
    }
}
