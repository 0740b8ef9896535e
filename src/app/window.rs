//! The winit 0.30 `ApplicationHandler`: the window, its wgpu surface (every status handled),
//! egui on top, the replay / record of input scripts, and `--exit-after-frames` /
//! `--screenshot` for end-to-end tests. Everything else lives in [`AppState`].

use std::sync::Arc;

use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::keyboard::PhysicalKey;
use winit::window::{Window, WindowId};

use super::panel::panel;
use super::replay::{key_from_winit, Button, Event, Key, Player, Recorder, Script};
use super::state::AppState;
use super::surface::{Acquired, SurfaceState};
use super::AppOptions;
use crate::error::{Error, Result};
use crate::gpu::Gpu;

/// Frames between two read-backs of the cull counters and GPU timers: each read-back waits
/// for the GPU, so doing it every frame would serialise CPU and GPU.
const STATS_EVERY: u64 = 10;

/// Everything that exists once the window is open.
struct Running {
    window: Arc<Window>,
    surface: SurfaceState,
    gpu: Gpu,
    egui_state: egui_winit::State,
    egui_renderer: egui_wgpu::Renderer,
    app: AppState,
    player: Option<Player>,
    recorder: Option<Recorder>,
    modifiers: egui::Modifiers,
}

/// The handler winit drives.
pub struct WindowApp {
    options: AppOptions,
    running: Option<Running>,
    /// `finish` ran (close and exit both call it).
    finished: bool,
    /// The first fatal error; `run` returns it after the loop ends.
    pub error: Option<Error>,
}

impl WindowApp {
    pub fn new(options: AppOptions) -> Self {
        Self {
            options,
            running: None,
            finished: false,
            error: None,
        }
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, e: Error) {
        if self.error.is_none() {
            self.error = Some(e);
        }
        event_loop.exit();
    }

    fn open(&mut self, event_loop: &ActiveEventLoop) -> Result<Running> {
        let o = &self.options;
        let attributes = Window::default_attributes()
            .with_title("sward")
            .with_inner_size(winit::dpi::PhysicalSize::new(o.size.0, o.size.1));
        let window = Arc::new(
            event_loop
                .create_window(attributes)
                .map_err(|e| Error::Gpu(format!("cannot open a window: {e}")))?,
        );
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_with_display_handle_from_env(
                Box::new(event_loop.owned_display_handle()),
            ));
        let surface = instance
            .create_surface(window.clone())
            .map_err(|e| Error::Gpu(format!("cannot create a surface for the window: {e}")))?;
        let gpu = Gpu::for_surface(instance, &surface, &o.adapter)?;
        eprintln!("adapter: {}", gpu.describe());
        let size = window.inner_size();
        let surface = SurfaceState::new(&gpu, surface, (size.width, size.height), o.vsync)?;
        let format = surface.format();

        let scene = match &o.scene {
            Some(path) => crate::scene::load_scene(path),
            None => super::state::default_scene(),
        };
        let mut app = AppState::new(&gpu, format, surface.size(), scene, o.scene.as_deref())?;
        app.fixed_dt = o.fixed_dt;
        app.budget.target_ms = o.target_frame_ms.or_else(|| {
            // A CPU adapter cannot draw the whole meadow at interactive rates: hold 10 fps.
            (gpu.info.device_type == wgpu::DeviceType::Cpu).then_some(90.0)
        });
        if let Some(path) = &o.save_path {
            app.scene_path = path.display().to_string();
        }

        let egui_ctx = egui::Context::default();
        let egui_state = egui_winit::State::new(
            egui_ctx,
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            None,
            Some(gpu.device.limits().max_texture_dimension_2d as usize),
        );
        let egui_renderer = egui_wgpu::Renderer::new(
            &gpu.device,
            surface.ui_format(),
            egui_wgpu::RendererOptions::default(),
        );
        let player = match &o.replay {
            Some(path) => Some(Player::new(Script::load(path)?)),
            None => None,
        };
        gpu.check_errors()?;
        Ok(Running {
            window,
            surface,
            gpu,
            egui_state,
            egui_renderer,
            app,
            player,
            recorder: o.record.as_ref().map(|_| Recorder::new()),
            modifiers: egui::Modifiers::default(),
        })
    }

    fn finish(&mut self) {
        if std::mem::replace(&mut self.finished, true) {
            return;
        }
        if let Some(r) = &self.running {
            // One line for logs and benchmarks: what the last frames cost on this adapter.
            let t = &r.app.frame_times;
            let last: Vec<f32> = t.iter().rev().take(100).copied().collect();
            if !last.is_empty() {
                let mean = last.iter().sum::<f32>() / last.len() as f32;
                eprintln!(
                    "{} frames; mean frame time of the last {}: {mean:.1} ms ({:.1} fps) on {}; frame budget: {}",
                    r.app.frame,
                    last.len(),
                    1000.0 / mean,
                    r.gpu.info.name,
                    r.app.budget.status()
                );
            }
        }
        if let (Some(r), Some(path)) = (&self.running, &self.options.record) {
            if let Some(rec) = &r.recorder {
                if let Err(e) = rec.script().save(path) {
                    self.error.get_or_insert(e);
                }
            }
        }
    }
}

/// The app's event for a winit event, when it is one the app uses.
fn translate(event: &WindowEvent) -> Option<Event> {
    match event {
        WindowEvent::CursorMoved { position, .. } => {
            Some(Event::CursorMoved(position.x as f32, position.y as f32))
        }
        WindowEvent::MouseInput { state, button, .. } => Some(Event::Button(
            Button::from_winit(*button)?,
            *state == ElementState::Pressed,
        )),
        WindowEvent::MouseWheel { delta, .. } => Some(Event::Scroll(match delta {
            MouseScrollDelta::LineDelta(_, y) => *y,
            // Trackpads report pixels; about 40 of them make one wheel notch.
            MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
        })),
        WindowEvent::KeyboardInput { event, .. } if !event.repeat => match event.physical_key {
            PhysicalKey::Code(code) => Some(Event::Key(
                key_from_winit(code)?,
                event.state == ElementState::Pressed,
            )),
            PhysicalKey::Unidentified(_) => None,
        },
        _ => None,
    }
}

impl Running {
    /// Feeds a replayed event to egui (as raw input) and to the app, as a window event
    /// would reach both.
    fn inject(&mut self, event: Event) {
        let ppp = self.window.scale_factor() as f32;
        match event {
            Event::Key(Key::Shift, down) => self.modifiers.shift = down,
            Event::Key(Key::Alt, down) => self.modifiers.alt = down,
            Event::Key(Key::Ctrl, down) => {
                self.modifiers.ctrl = down;
                self.modifiers.command = down;
            }
            _ => {}
        }
        let modifiers = self.modifiers;
        let cursor = self.app.input.cursor.unwrap_or_default();
        let pos = |x: f32, y: f32| egui::pos2(x / ppp, y / ppp);
        let egui_event = match event {
            Event::CursorMoved(x, y) => Some(egui::Event::PointerMoved(pos(x, y))),
            Event::Button(b, pressed) => Some(egui::Event::PointerButton {
                pos: pos(cursor.x, cursor.y),
                button: b.to_egui(),
                pressed,
                modifiers,
            }),
            Event::Key(k, pressed) => k.to_egui().map(|key| egui::Event::Key {
                key,
                physical_key: Some(key),
                pressed,
                repeat: false,
                modifiers,
            }),
            Event::Scroll(lines) => Some(egui::Event::MouseWheel {
                unit: egui::MouseWheelUnit::Line,
                delta: egui::vec2(0.0, lines),
                phase: egui::TouchPhase::Move,
                source: egui::MouseWheelSource::Unknown,
                modifiers,
            }),
        };
        if let Some(e) = egui_event {
            self.egui_state.egui_input_mut().events.push(e);
        }
        let ctx = self.egui_state.egui_ctx();
        let pointer = ctx.is_pointer_over_egui() || ctx.egui_wants_pointer_input();
        let keyboard = ctx.egui_wants_keyboard_input();
        self.app.handle(event, pointer, keyboard);
    }

    /// One frame: replayed input, CPU update, scene + arrows + panel, present. Returns
    /// whether a frame was drawn (a minimised window or a busy surface skips it).
    fn redraw(&mut self, options: &AppOptions) -> Result<bool> {
        let acquired = self.surface.acquire(&self.gpu);
        let texture = match acquired {
            Acquired::Frame(t) => t,
            Acquired::Skip => return Ok(false),
        };
        if let Some(player) = &mut self.player {
            for e in player.due(self.app.frame) {
                self.inject(e);
            }
        }
        let dt = self.app.update(&self.gpu);

        let raw = self.egui_state.take_egui_input(&self.window);
        let app = &mut self.app;
        let gpu = &self.gpu;
        let out = self
            .egui_state
            .egui_ctx()
            .run_ui(raw, |ui| panel(ui, app, gpu));
        self.egui_state
            .handle_platform_output(&self.window, out.platform_output);
        let ppp = out.pixels_per_point;
        let jobs = self.egui_state.egui_ctx().tessellate(out.shapes, ppp);

        let view = texture
            .texture
            .create_view(&wgpu::TextureViewDescriptor::default());
        let ui_view = texture.texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some("sward.window.ui_view"),
            format: Some(self.surface.ui_format()),
            ..Default::default()
        });
        let mut encoder = self
            .gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("sward.window.frame"),
            });
        self.app.size = self.surface.size();
        self.app
            .encode(&self.gpu, &mut encoder, dt, &view, self.surface.depth());

        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [self.surface.size().0, self.surface.size().1],
            pixels_per_point: ppp,
        };
        for (id, deltas) in &out.textures_delta.set {
            for delta in deltas {
                self.egui_renderer
                    .update_texture(&self.gpu.device, &self.gpu.queue, *id, delta);
            }
        }
        let extra = self.egui_renderer.update_buffers(
            &self.gpu.device,
            &self.gpu.queue,
            &mut encoder,
            &jobs,
            &screen,
        );
        {
            let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("sward.window.egui"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &ui_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Load,
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            let mut pass = pass.forget_lifetime();
            self.egui_renderer.render(&mut pass, &jobs, &screen);
        }
        for id in &out.textures_delta.free {
            self.egui_renderer.free_texture(id);
        }
        self.gpu
            .queue
            .submit(extra.into_iter().chain([encoder.finish()]));
        self.gpu.check_errors()?;

        let last = options.exit_after_frames == Some(self.app.frame);
        if last {
            if let Some(path) = &options.screenshot {
                if !self.surface.can_read_back() {
                    return Err(Error::Gpu(format!(
                        "cannot save {}: this platform's window surface cannot be read back",
                        path.display()
                    )));
                }
                let image = crate::render::target::read_texture(&self.gpu, &texture.texture)?;
                crate::output::save_png(path, &image)?;
                eprintln!("wrote {}", path.display());
            }
        }
        self.window.pre_present_notify();
        self.gpu.queue.present(texture);
        if self.app.frame.is_multiple_of(STATS_EVERY) {
            self.app.read_stats(&self.gpu);
        }
        Ok(true)
    }
}

impl ApplicationHandler for WindowApp {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.running.is_some() {
            return;
        }
        match self.open(event_loop) {
            Ok(r) => {
                r.window.request_redraw();
                self.running = Some(r);
            }
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(r) = &mut self.running else {
            return;
        };
        let response = r.egui_state.on_window_event(&r.window, &event);
        match &event {
            WindowEvent::CloseRequested => {
                self.finish();
                event_loop.exit();
                return;
            }
            WindowEvent::Resized(size) => {
                // Zero while minimised: the surface keeps its old size and frames are skipped.
                r.surface.resize(&r.gpu, (size.width, size.height));
            }
            WindowEvent::ScaleFactorChanged { .. } => {
                let size = r.window.inner_size();
                r.surface.resize(&r.gpu, (size.width, size.height));
            }
            WindowEvent::Focused(false) => r.app.input.release_all(),
            WindowEvent::ModifiersChanged(m) => {
                let s = m.state();
                r.modifiers = egui::Modifiers {
                    alt: s.alt_key(),
                    ctrl: s.control_key(),
                    shift: s.shift_key(),
                    mac_cmd: false,
                    command: s.control_key(),
                };
            }
            WindowEvent::RedrawRequested => {
                let options = self.options.clone();
                match r.redraw(&options) {
                    Ok(_) => {
                        if options.exit_after_frames.is_some_and(|n| r.app.frame >= n) {
                            self.finish();
                            event_loop.exit();
                            return;
                        }
                    }
                    Err(e) => {
                        self.fail(event_loop, e);
                        return;
                    }
                }
            }
            _ => {}
        }
        if let Some(e) = translate(&event) {
            // A replay drives the input alone: the real mouse over the window must not
            // disturb a scripted session.
            if r.player.is_none() {
                if let Some(rec) = &mut r.recorder {
                    rec.push(r.app.frame, e);
                }
                let ctx = r.egui_state.egui_ctx();
                let pointer = response.consumed || ctx.is_pointer_over_egui();
                let keyboard = ctx.egui_wants_keyboard_input();
                r.app.handle(e, pointer, keyboard);
            }
        }
    }

    fn about_to_wait(&mut self, _event_loop: &ActiveEventLoop) {
        // Continuous rendering: the grass moves even when the user does not.
        if let Some(r) = &self.running {
            r.window.request_redraw();
        }
    }

    fn exiting(&mut self, _event_loop: &ActiveEventLoop) {
        self.finish();
    }
}

/// Opens the window and runs until it is closed (or `--exit-after-frames` frames).
pub fn run(options: AppOptions) -> Result<()> {
    let event_loop = EventLoop::new().map_err(|e| {
        Error::Gpu(format!(
            "cannot open a window: {e} (no display? set DISPLAY or WAYLAND_DISPLAY, or run \
             under xvfb-run; `sward render` works without a display)"
        ))
    })?;
    let mut app = WindowApp::new(options);
    event_loop
        .run_app(&mut app)
        .map_err(|e| Error::Gpu(format!("the window's event loop failed: {e}")))?;
    match app.error.take() {
        Some(e) => Err(e),
        None => Ok(()),
    }
}
