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
use super::ui_cache::{self, UiCache};
use super::AppOptions;
use sward::error::{Error, Result};
use sward::gpu::Gpu;
use sward::output::Outputs;

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
    /// The panel as egui last drew it, composited over each frame.
    ui_cache: UiCache,
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
    /// `--screenshot` and `--record`, checked before the window opened and renamed into
    /// place together at the end, only when the run succeeded.
    outputs: Option<Outputs>,
    /// The `--replay` script, read and checked before the window opened.
    script: Option<Script>,
    /// The scene (or why it failed to load), read before the window opened.
    scene: Option<Result<sward::scene::Scene>>,
}

impl WindowApp {
    /// Checks everything the run reads and writes before a window opens: the replay script
    /// is parsed, the output paths are vetted (no device or FIFO, no output over an input
    /// such as `--replay S --record S`, no two outputs on one file).
    pub fn new(options: AppOptions) -> Result<Self> {
        let mut outputs = Outputs::new();
        if let Some(scene) = &options.scene {
            outputs.input("--scene", scene)?;
        }
        if let Some(replay) = &options.replay {
            outputs.input("--replay", replay)?;
        }
        if let Some(path) = &options.screenshot {
            outputs.add("--screenshot", path)?;
        }
        if let Some(path) = &options.record {
            outputs.add("--record", path)?;
        }
        if let Some(path) = &options.trace {
            outputs.add("--trace", path)?;
        }
        let script = options.replay.as_deref().map(Script::load).transpose()?;
        let scene = sward::commands::load(options.scene.as_deref(), &options.sets);
        // A bad --set is a mistake on the command line, not in a file the user may want to
        // fix from the panel: it stops the run like every other bad flag. A scene file
        // that fails to load opens the default meadow with the error in the panel.
        if let Err(e @ Error::Set { .. }) = scene {
            return Err(e);
        }
        Ok(Self {
            scene: Some(scene),
            options,
            running: None,
            finished: false,
            error: None,
            outputs: Some(outputs),
            script,
        })
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
                .map_err(|e| Error::Window(format!("cannot open a window: {}", os_message(&e))))?,
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

        let scene = self
            .scene
            .take()
            .unwrap_or_else(|| sward::commands::load(o.scene.as_deref(), &o.sets));
        let mut app = AppState::new(
            &gpu,
            format,
            surface.size(),
            scene,
            o.scene.as_deref(),
            &o.sets,
        )?;
        app.fixed_dt = o.fixed_dt;
        if o.trace.is_some() {
            app.renderer.record_trace();
        }
        if o.count_work && !app.renderer.count_work(&gpu, true) {
            log::warn!("--count-work: this adapter has no pipeline-statistics queries");
        }
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
        let ui_cache = UiCache::new(&gpu.device, surface.ui_format(), surface.size());
        let egui_renderer = egui_wgpu::Renderer::new(
            &gpu.device,
            surface.ui_format(),
            egui_wgpu::RendererOptions::default(),
        );
        let player = self.script.take().map(Player::new);
        gpu.check_errors()?;
        Ok(Running {
            window,
            surface,
            gpu,
            egui_state,
            egui_renderer,
            ui_cache,
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
                let (w, h) = r.app.render_size();
                let tiles = r.app.stats.tiles.map_or(String::new(), |t| {
                    format!(
                        "; tiles: {} resident, {} generated",
                        t.resident, t.generated_total
                    )
                });
                eprintln!(
                    "{} frames; mean frame time of the last {}: {mean:.1} ms ({:.1} fps) on {}; \
                     blades drawn in the last read-back: {}; billboards drawn: {}; 3D passes \
                     at {w}x{h}; frame budget: {}{tiles}",
                    r.app.frame,
                    last.len(),
                    1000.0 / mean,
                    r.gpu.info.name,
                    r.app.stats.counters.drawn(),
                    r.app.stats.billboards_drawn,
                    r.app.budget.status()
                );
            }
            if let Some(w) = &r.app.walker {
                eprintln!(
                    "walk mode: the character walked {:.2} m and stands at ({:.2}, {:.2}), \
                     heading {:.1}°",
                    w.walked,
                    w.position.x,
                    w.position.y,
                    w.heading.to_degrees()
                );
            }
        }
        if let Err(e) = self.write_outputs() {
            self.error.get_or_insert(e);
        }
        // Dropping the outputs of a failed run removes their temporary files: an existing
        // --record or --screenshot file stays as it was.
        self.outputs = None;
    }

    /// Stages the recorded script and renames it and the screenshot into place, unless the
    /// run failed (an error, or a Save that failed in an `--exit-after-frames` run).
    fn write_outputs(&mut self) -> Result<()> {
        if self.error.is_some() {
            return Ok(());
        }
        let (Some(r), Some(outputs)) = (&mut self.running, &mut self.outputs) else {
            return Ok(());
        };
        if self.options.exit_after_frames.is_some() {
            if let Some(message) = &r.app.failed_save {
                return Err(Error::Invalid(format!(
                    "a Save failed during this run, so it exits with an error and writes \
                     no output: {message}"
                )));
            }
        }
        if let (Some(path), Some(rec)) = (&self.options.record, &r.recorder) {
            outputs.write(path, rec.script().to_text(path)?.as_bytes())?;
        }
        if let Some(path) = &self.options.trace {
            // The frames of the renderer in use at the end (a field rebuilt from the panel
            // starts a new renderer, and its trace, from there).
            let tracks = [sward::render::timing::TraceTrack {
                name: "sward window".into(),
                scopes: r.app.renderer.take_trace(&r.gpu)?,
            }];
            sward::render::timing::write_trace(outputs, path, &tracks, r.gpu.timestamps)?;
        }
        if let Some(path) = &self.options.screenshot {
            if !outputs.is_written(path) {
                // Closed before the last frame: there is no screenshot to write, and the
                // rest of the run's outputs still land.
                eprintln!(
                    "no screenshot: the window closed at frame {}, before --exit-after-frames",
                    r.app.frame
                );
                outputs.forget(path);
            }
        }
        if let Some(outputs) = self.outputs.take() {
            outputs.commit()?;
            for path in [
                &self.options.screenshot,
                &self.options.record,
                &self.options.trace,
            ]
            .into_iter()
            .flatten()
            {
                eprintln!("wrote {}", path.display());
            }
        }
        Ok(())
    }
}

/// A winit OS error's message without the source location winit puts in front of it
/// (`os error at /path/to/winit/src/…:765: message`), which names the build machine.
fn os_message(e: &dyn std::fmt::Display) -> String {
    let text = e.to_string();
    match text.strip_prefix("os error at ") {
        Some(rest) => rest
            .split_once(": ")
            .map(|(_, message)| message.to_string())
            .unwrap_or(rest.to_string()),
        None => text,
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
    fn redraw(&mut self, options: &AppOptions, outputs: Option<&mut Outputs>) -> Result<bool> {
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
        let mut out = self
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
            .encode(&self.gpu, &mut encoder, dt, &view, self.surface.depth())?;

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
        // egui draws into the panel's cache only when its output changed; the cache is
        // composited over every frame (`app::ui_cache`).
        let textures_changed =
            !out.textures_delta.set.is_empty() || !out.textures_delta.free.is_empty();
        let redraw = self.ui_cache.stale(
            &self.gpu.device,
            &jobs,
            textures_changed,
            self.surface.size(),
            ppp,
        );
        let extra = if redraw {
            self.egui_renderer.update_buffers(
                &self.gpu.device,
                &self.gpu.queue,
                &mut encoder,
                &jobs,
                &screen,
            )
        } else {
            Vec::new()
        };
        // The panel is part of the frame: timed and counted like the 3D passes.
        let egui_renderer = &self.egui_renderer;
        let cache = &self.ui_cache;
        self.app
            .renderer
            .encode_timed(&mut encoder, sward::render::timing::UI, |e, q| {
                if redraw {
                    let transparent = wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT);
                    let writes = q.render_writes_part(true, false);
                    let pass =
                        ui_cache::pass(e, "sward.window.egui", cache.view(), transparent, writes);
                    let mut pass = pass.forget_lifetime();
                    q.begin(&mut pass);
                    egui_renderer.render(&mut pass, &jobs, &screen);
                    q.end(&mut pass);
                }
                let writes = q.render_writes_part(!redraw, true);
                let mut pass = ui_cache::pass(
                    e,
                    "sward.window.ui_composite",
                    &ui_view,
                    wgpu::LoadOp::Load,
                    writes,
                );
                q.begin(&mut pass);
                cache.composite(&mut pass);
                q.end(&mut pass);
            });
        self.app.finish_frame(&mut encoder);
        for id in &out.textures_delta.free {
            self.egui_renderer.free_texture(id);
        }
        // Applied above: epaint asserts (in debug builds) that no delta is dropped unhandled.
        out.textures_delta.clear();
        let index = self
            .gpu
            .queue
            .submit(extra.into_iter().chain([encoder.finish()]));
        self.app.renderer.frame_submitted(&self.gpu, index);
        self.gpu.check_errors()?;

        let last = options.exit_after_frames == Some(self.app.frame);
        if last {
            if let (Some(path), Some(outputs)) = (&options.screenshot, outputs) {
                if !self.surface.can_read_back() {
                    return Err(Error::Gpu(format!(
                        "cannot save {}: this platform's window surface cannot be read back",
                        path.display()
                    )));
                }
                let image = sward::render::target::read_texture(&self.gpu, &texture.texture)?;
                // Staged: renamed into place with --record when the run ends well.
                outputs.write_png(path, &image)?;
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
            // A replay holds its own keys: the window losing the focus (Xvfb hands it
            // around while the window maps, sometimes a few frames in) must not release a
            // scripted Alt between its press and the click it modifies.
            WindowEvent::Focused(false) if r.player.is_none() => r.app.input.release_all(),
            WindowEvent::ModifiersChanged(m) if r.player.is_none() => {
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
                match r.redraw(&options, self.outputs.as_mut()) {
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
    // Inputs and outputs first: a bad replay script or output path is reported before a
    // window (or a display) is needed.
    let mut app = WindowApp::new(options)?;
    check_display()?;
    let event_loop = EventLoop::new().map_err(|e| {
        Error::Window(format!(
            "cannot connect to the display: {} ({}); is a display server running there? \
             `xvfb-run sward …` gives sward a virtual one (Debian/Ubuntu: apt-get install \
             xvfb), and `sward render` draws the same frames to PNG without a display",
            os_message(&e),
            display_names()
        ))
    })?;
    event_loop
        .run_app(&mut app)
        .map_err(|e| Error::Window(format!("the window's event loop failed: {e}")))?;
    match app.error.take() {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

/// The display variables winit looks at, as set now.
fn display_names() -> String {
    ["DISPLAY", "WAYLAND_DISPLAY", "WAYLAND_SOCKET"]
        .iter()
        .map(|v| match std::env::var_os(v) {
            Some(value) => format!("{v}={}", value.to_string_lossy()),
            None => format!("{v} unset"),
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// The window needs a display: without one, say so and how to get one (on Linux winit
/// reads these variables; elsewhere there is always a display).
fn check_display() -> Result<()> {
    if !cfg!(target_os = "linux") {
        return Ok(());
    }
    let any = ["DISPLAY", "WAYLAND_DISPLAY", "WAYLAND_SOCKET"]
        .iter()
        .any(|v| std::env::var_os(v).is_some_and(|s| !s.is_empty()));
    if any {
        return Ok(());
    }
    Err(Error::Window(
        "cannot open the window: there is no display (neither DISPLAY nor WAYLAND_DISPLAY is \
         set). Run sward in a desktop session, or give it a virtual display with \
         `xvfb-run sward …` (Debian/Ubuntu: apt-get install xvfb); `sward render` draws the \
         same frames to PNG without any display"
            .into(),
    ))
}
