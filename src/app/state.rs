//! The window's state apart from the window itself: the renderer and its scene, the camera,
//! the AGC editor, the balls, the frame budget and what the panel shows. Input arrives as
//! [`Event`]s (from winit or from a replayed script), frames are encoded (`frame`) into any
//! colour view, so all of it runs the same under a real window, Xvfb or a test.

use std::collections::VecDeque;
use std::path::{Path, PathBuf};
use std::time::Instant;

use glam::{Vec2, Vec3};

use super::adaptive::FrameBudget;
use super::balls::Balls;
use super::camera::{centre_offset, CameraController, CameraMode};
use super::editor::{Editor, Selection};
use super::input::InputState;
use super::picking::{pick_point, pick_terrain, screen_ray};
use super::replay::{Button, Event, Key};
use super::walker::Walker;
use sward::embed::GrassRenderer;
use sward::error::{Error, Result};
use sward::gpu::Gpu;
use sward::render::arrows::{ArrowPass, ARROW_LIFT};
use sward::render::camera::CameraView;
use sward::render::post::HDR_FORMAT;
use sward::render::upscale::{scaled_size, Upscale};
use sward::render::FrameStats;
use sward::scene::save::save_scene;
use sward::scene::{load_scene, parse_scene, Scene, WindSource};

mod frame;

/// The Stats' frame times and budget line as last refreshed.
#[derive(Clone, Debug, Default)]
pub struct ShownStats {
    pub frame_times: Vec<f32>,
    pub budget: String,
}

/// What a left click does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Clicks throw balls.
    Play,
    /// Clicks place, select and drag AGC guide points.
    Edit,
}

/// Speed of a thrown ball in m/s and its radius in metres.
pub const THROW_SPEED: f32 = 14.0;
pub const BALL_RADIUS: f32 = 0.35;
/// Radius of the steered character ball.
pub const CHARACTER_RADIUS: f32 = 0.45;
/// Height above its origin (its feet) of the walker's chest, which the camera behind it
/// looks at, in the object's units (times its scale); the figure's hips are at 0.95.
pub const WALKER_CHEST: f32 = 1.2;
/// How close (pixels) the cursor must be to a guide point to pick it.
pub const PICK_RADIUS_PX: f32 = 14.0;
/// Wind grid the first guide switches to on a CPU adapter.
pub const SOFTWARE_GRID: u32 = 128;
/// The narrowest 3D view beside the panel, in pixels; a panel wider than the window less
/// this leaves the view the whole window (under the panel).
pub const MIN_VIEW_PX: u32 = 64;
/// The region of a window of `size` beside a panel `panel_px` wide, `[x, y, width, height]`
/// ([`AppState::view_region`]).
pub fn view_region((w, h): (u32, u32), panel_px: u32) -> [u32; 4] {
    let left = if panel_px.saturating_add(MIN_VIEW_PX) <= w {
        panel_px
    } else {
        0
    };
    [left, 0, w - left, h]
}

/// Frame times kept for the Stats plot.
pub const PLOT_FRAMES: usize = 300;

/// A message for the panel's status line.
#[derive(Clone, Debug, PartialEq)]
pub enum Status {
    Info(String),
    Error(String),
}

/// Everything the window shows and edits.
pub struct AppState {
    pub renderer: GrassRenderer,
    pub camera: CameraController,
    pub editor: Editor,
    applied_revision: u64,
    pub balls: Balls,
    /// The scene's animated character while the user steers it (walk mode, `G`); it keeps
    /// standing where it was left when the camera leaves walk mode.
    pub walker: Option<Walker>,
    pub budget: FrameBudget,
    pub mode: Mode,
    pub input: InputState,
    arrows: ArrowPass,
    /// The 3D passes at the frame budget's render scale, stretched over the window.
    upscale: Upscale,
    pub hover: Option<Selection>,
    /// Path typed in the panel for Save / Load.
    pub scene_path: String,
    /// A scene file that failed to load (at start or by Load): Save refuses to write over
    /// it, since the user's work in it would be lost, until the user picks that path again
    /// (edits the path in the panel).
    pub unsaveable: Option<PathBuf>,
    /// The last Save that failed or was refused, for `--exit-after-frames` runs: such a run
    /// exits non-zero.
    pub failed_save: Option<String>,
    /// The field settings the next "Regenerate" applies.
    pub field_draft: sward::scene::Field,
    /// The trail map settings the next "Apply" of the Physics section builds.
    pub trails_draft: Option<sward::scene::Trails>,
    pub status: Option<Status>,
    pub show_help: bool,
    /// Wall-clock milliseconds of the last frames (the Stats plot).
    pub frame_times: VecDeque<f32>,
    /// What the Stats show of the frame times and the budget, refreshed with the GPU
    /// figures (`read_stats`) rather than every frame, so the panel's picture holds still
    /// between refreshes and its cache is reused (`app::ui_cache`).
    pub shown: ShownStats,
    pub stats: FrameStats,
    /// Tiles generated per second, measured between the last two stats read-backs.
    pub tile_rate: f32,
    /// The far levels' light gain as last read (`render::far_gain`; `None` before the first
    /// measurement).
    pub far_gain: Option<Vec3>,
    /// The blades' ratio to the far light model, the cards' contrast gain and the far
    /// field's distance gain as last read (`Renderer::far_calibration`).
    pub far_calibration: sward::render::far_gain::FarCalibration,
    /// When the last stats were read and the tiles generated by then.
    tile_mark: Option<(Instant, u64)>,
    /// Seconds per frame when fixed (replays, tests); otherwise the wall clock's.
    pub fixed_dt: Option<f32>,
    /// Whether the simulation advances.
    pub paused: bool,
    pub format: wgpu::TextureFormat,
    pub size: (u32, u32),
    /// Window pixels the panel covers from the left edge (its right edge; 0 without a
    /// panel): the 3D passes draw only the view beside it.
    pub panel_px: u32,
    pub frame: u64,
    last_frame: Option<Instant>,
    /// The adapter is a CPU one (lavapipe): the defaults favour frame time.
    pub software: bool,
}

/// Whether `scene` has an animated object for walk mode (then no character ball is spawned).
fn has_character(scene: &Scene) -> bool {
    scene.objects.iter().any(|o| o.animation.is_some())
}

/// The default meadow, parsed from the built-in scene.
pub fn default_scene() -> Result<Scene> {
    parse_scene(
        sward::commands::DEFAULT_SCENE,
        Path::new(sward::commands::DEFAULT_SCENE_PATH),
    )
}

/// Validates a scene edited in memory by writing it and loading it back through the same
/// checks as a file; errors name the field and the allowed range.
pub fn validated(scene: &Scene) -> Result<Scene> {
    let text = sward::scene::save::scene_to_string(scene)?;
    parse_scene(&text, Path::new("(panel)"))
}

impl AppState {
    /// Builds the state for `scene`; when it failed to load, opens the default scene (with
    /// `sets`, the command line's `--set` overrides) and shows the error in the panel.
    pub fn new(
        gpu: &Gpu,
        format: wgpu::TextureFormat,
        size: (u32, u32),
        scene: Result<Scene>,
        path: Option<&Path>,
        sets: &[String],
    ) -> Result<Self> {
        let failed_path = scene
            .is_err()
            .then(|| path.map(Path::to_path_buf))
            .flatten();
        let (scene, status) = match scene {
            Ok(s) => (s, None),
            Err(e) => {
                eprintln!("error: {e}\nopening the default meadow instead");
                (
                    // The default meadow, with the command line's --set still applied.
                    sward::commands::load(None, sets)?,
                    Some(Status::Error(format!(
                        "{e} — the default meadow was opened instead; Save will not write \
                         over the file that failed to load"
                    ))),
                )
            }
        };
        let (renderer, editor) = build(gpu, scene, format)?;
        // A scene camera that follows an object opens behind it.
        let camera = CameraController::from_view(
            &renderer.scene_camera(&CameraView::from_scene(&renderer.scene.camera), 0.0),
        );
        let budget = FrameBudget::new(&renderer.scene.culling, None)
            .with_msaa_step(true)
            .with_grass_shadow_step(true)
            .with_fold_step(true)
            .with_lod_step(true)
            .with_morph_step(true)
            .with_billboard_step(true);
        let mut balls = Balls::new();
        // The scene camera's target point, kept as the orbit centre. A scene with an
        // animated character has it walk (G) instead of a ball in its way.
        let target = camera.orbit_center;
        if !has_character(&renderer.scene) {
            balls.spawn_character((target.x, target.z), CHARACTER_RADIUS, &renderer.terrain);
        }
        let applied_revision = editor.revision();
        let field_draft = renderer.scene.field.clone();
        let trails_draft = renderer.scene.physics.trails.clone();
        Ok(Self {
            arrows: ArrowPass::new(gpu, HDR_FORMAT, renderer.msaa_samples()),
            upscale: Upscale::new(gpu, format),
            renderer,
            camera,
            editor,
            applied_revision,
            balls,
            walker: None,
            budget,
            mode: Mode::Play,
            input: InputState::default(),
            hover: None,
            scene_path: path
                .map(|p| p.display().to_string())
                .unwrap_or_else(|| "scene.ron".to_string()),
            unsaveable: failed_path,
            failed_save: None,
            field_draft,
            trails_draft,
            status,
            show_help: false,
            frame_times: VecDeque::with_capacity(PLOT_FRAMES),
            shown: ShownStats::default(),
            panel_px: 0,
            stats: FrameStats::default(),
            tile_rate: 0.0,
            far_gain: None,
            far_calibration: Default::default(),
            tile_mark: None,
            fixed_dt: None,
            paused: false,
            format,
            size,
            frame: 0,
            last_frame: None,
            software: gpu.info.device_type == wgpu::DeviceType::Cpu,
        })
    }

    /// The camera the frame is drawn from.
    pub fn view(&self) -> CameraView {
        self.camera.view()
    }

    /// The ball the follow camera tracks: the character, else the last thrown ball.
    pub fn followed(&self) -> Option<Vec3> {
        self.balls
            .character
            .as_ref()
            .or(self.balls.thrown.last())
            .map(|b| b.center)
    }

    /// Handles one input event. `egui_pointer` / `egui_keyboard`: the panel uses the pointer
    /// or the keyboard now, so the scene must not.
    pub fn handle(&mut self, event: Event, egui_pointer: bool, egui_keyboard: bool) {
        // Releases always reach the state, or a key would stay held after egui took focus.
        let release = matches!(event, Event::Key(_, false) | Event::Button(_, false));
        if release {
            self.input.apply(event);
            if event == Event::Button(Button::Left, false) && self.editor.is_dragging() {
                self.editor.release();
            }
            return;
        }
        match event {
            Event::CursorMoved(..) => {
                self.input.apply(event);
                if self.mode == Mode::Edit && self.editor.is_dragging() {
                    let ground = self.ground_under_cursor();
                    self.editor.drag(ground);
                }
            }
            Event::Scroll(_) if egui_pointer => {}
            Event::Scroll(_) => {
                self.input.apply(event);
            }
            Event::Button(..) if egui_pointer => {}
            Event::Button(b, true) => {
                self.input.apply(event);
                if b == Button::Left {
                    self.left_press();
                }
            }
            Event::Key(..) if egui_keyboard => {}
            Event::Key(k, true) => {
                let repeat = self.input.held(k);
                self.input.apply(event);
                if !repeat {
                    self.key_press(k);
                }
            }
            Event::Button(_, false) | Event::Key(_, false) => {}
        }
    }

    /// The terrain point (x, z) under the cursor.
    fn ground_under_cursor(&self) -> Option<Vec2> {
        let cursor = self.input.cursor?;
        let ray = screen_ray(&self.view(), self.size, cursor);
        let far = self.camera.far;
        pick_terrain(&ray, &self.renderer.terrain, far).map(|p| Vec2::new(p.x, p.z))
    }

    /// The guide point under the cursor.
    fn point_under_cursor(&self) -> Option<Selection> {
        let cursor = self.input.cursor?;
        pick_point(
            self.editor.guides(),
            &self.renderer.terrain,
            &self.view(),
            self.size,
            cursor,
            PICK_RADIUS_PX,
            ARROW_LIFT,
        )
    }

    fn left_press(&mut self) {
        match self.mode {
            Mode::Edit => {
                let hit = self.point_under_cursor();
                let ground = self.ground_under_cursor();
                let alt = self.input.held(Key::Alt);
                self.editor.press(hit, ground, alt);
            }
            Mode::Play => {
                if let Some(cursor) = self.input.cursor {
                    let ray = screen_ray(&self.view(), self.size, cursor);
                    self.throw(ray.dir);
                }
            }
        }
    }

    /// Throws a ball from just in front of the camera along `dir`.
    pub fn throw(&mut self, dir: Vec3) {
        let view = self.view();
        let origin = view.eye + dir.normalize_or(Vec3::NEG_Z) * 1.0;
        self.balls.throw(origin, dir, THROW_SPEED, BALL_RADIUS);
    }

    fn key_press(&mut self, key: Key) {
        let ctrl = self.input.ctrl();
        match key {
            Key::Z if ctrl && self.input.held(Key::Shift) => {
                self.editor.redo();
            }
            Key::Z if ctrl => {
                self.editor.undo();
            }
            Key::Y if ctrl => {
                self.editor.redo();
            }
            Key::S if ctrl => self.save(),
            Key::Tab => self.toggle_mode(),
            Key::Space => {
                let dir = self.camera.forward();
                self.throw(dir);
            }
            Key::Delete if self.mode == Mode::Edit => self.editor.delete_selected(),
            Key::Escape => self.editor.select(None),
            Key::O => self.toggle_camera(CameraMode::Orbit),
            Key::F => self.toggle_camera(CameraMode::Follow),
            Key::G => self.toggle_walk(),
            Key::C if !ctrl => self.balls.clear(),
            Key::H | Key::F1 => self.show_help = !self.show_help,
            _ => {}
        }
    }

    pub fn toggle_mode(&mut self) {
        self.mode = match self.mode {
            Mode::Play => Mode::Edit,
            Mode::Edit => Mode::Play,
        };
        self.hover = None;
    }

    /// Switches to `mode`, or back to flying when it is already on.
    pub fn toggle_camera(&mut self, mode: CameraMode) {
        let next = if self.camera.mode == mode {
            CameraMode::Fly
        } else {
            mode
        };
        let follow = self.followed();
        self.camera.set_mode(next, follow);
    }

    /// Walk mode on or off: the camera goes behind the scene's animated character and W/S/A/D
    /// steer it (taken over where its path has it now), or back to flying, the character
    /// standing where it was left. A scene without an animated object says so instead.
    pub fn toggle_walk(&mut self) {
        if self.camera.mode == CameraMode::Behind {
            self.camera.set_mode(CameraMode::Fly, None);
            return;
        }
        if self.walker.is_none() {
            let r = &self.renderer;
            self.walker = Walker::take(&r.scene, &r.terrain, r.time, |i| r.animation_duration(i));
        }
        let Some(w) = self.walker else {
            self.status = Some(Status::Info(
                "walk mode needs an animated character: this scene has no object with an \
                 `animation` (assets/scenes/walk.ron has one)"
                    .into(),
            ));
            return;
        };
        self.pose_walker();
        self.camera.track_heading(w.heading);
        let chest = self.walker_chest();
        self.camera.set_mode(CameraMode::Behind, chest);
    }

    /// The point the camera behind the walker looks at: its chest.
    fn walker_chest(&self) -> Option<Vec3> {
        let w = self.walker.as_ref()?;
        let scale = self.renderer.scene.objects.get(w.object)?.scale;
        Some(w.pose(&self.renderer.terrain).origin + Vec3::Y * WALKER_CHEST * scale)
    }

    /// Hands the renderer the walker's pose (again each frame: a scene edited in the panel
    /// is a new scene without it).
    fn pose_walker(&mut self) {
        let Some(w) = self.walker else { return };
        let pose = w.pose(&self.renderer.terrain);
        if let Err(e) = self.renderer.pose_object(w.object, Some(pose)) {
            // The scene lost the object (it cannot, short of a new scene): stop steering.
            self.status = Some(Status::Error(format!("walk mode stopped: {e}")));
            self.walker = None;
        }
    }

    /// The scene as it is now (guides from the editor, camera from the controller), for
    /// saving.
    pub fn current_scene(&self) -> Scene {
        let mut scene = self.renderer.scene.clone();
        scene.wind.guides = self.editor.guides().to_vec();
        let view = self.view();
        scene.camera.eye = view.eye.into();
        scene.camera.target = view.target.into();
        scene
    }

    /// Saves the scene to the panel's path (temporary file + rename: a failed save leaves
    /// the old file and the scene in memory as they were).
    pub fn save(&mut self) {
        let path = PathBuf::from(self.scene_path.trim());
        let refused = self
            .unsaveable
            .as_deref()
            .is_some_and(|failed| sward::output::same_file(failed, &path));
        let result = if path.as_os_str().is_empty() {
            Err("no path: type where to save in the panel".to_string())
        } else if refused {
            Err(format!(
                "{} failed to load, and Save does not write over a file it could not read \
                 (what is in it would be lost); type the path again in the panel to save \
                 there anyway, or choose another",
                path.display()
            ))
        } else {
            save_scene(&self.current_scene(), &path).map_err(|e| e.to_string())
        };
        self.status = Some(match result {
            Ok(()) => Status::Info(format!("saved {}", path.display())),
            Err(e) => {
                let message = format!("not saved: {e}");
                self.failed_save = Some(message.clone());
                Status::Error(message)
            }
        });
    }

    /// Loads the scene at the panel's path; on error the current scene stays.
    pub fn load(&mut self, gpu: &Gpu) {
        let path = PathBuf::from(self.scene_path.trim());
        let loaded = load_scene(&path);
        if loaded.is_err() {
            // The path stays in the panel, so that the user can fix the file and load it
            // again; Save must not write the current scene over it meanwhile.
            self.unsaveable = Some(path.clone());
        }
        let result = loaded.and_then(|scene| self.replace_scene(gpu, scene));
        self.status = Some(match result {
            Ok(()) => {
                self.unsaveable = None;
                Status::Info(format!("loaded {}", path.display()))
            }
            Err(e) => Status::Error(format!("not loaded: {e}")),
        });
    }

    /// Rebuilds everything for a new scene (Load) and moves the camera to its view.
    pub fn replace_scene(&mut self, gpu: &Gpu, scene: Scene) -> Result<()> {
        let (renderer, editor) = build(gpu, scene, self.format)?;
        let overlay = self.renderer.overlay_enabled();
        self.renderer = renderer;
        if overlay {
            self.renderer.enable_overlay(gpu, self.format);
        }
        self.editor = editor;
        self.applied_revision = self.editor.revision();
        self.camera = CameraController::from_view(
            &self
                .renderer
                .scene_camera(&CameraView::from_scene(&self.renderer.scene.camera), 0.0),
        );
        self.field_draft = self.renderer.scene.field.clone();
        self.trails_draft = self.renderer.scene.physics.trails.clone();
        self.budget = FrameBudget::new(&self.renderer.scene.culling, self.budget.target_ms)
            .with_msaa_step(true)
            .with_grass_shadow_step(true)
            .with_fold_step(true)
            .with_lod_step(true)
            .with_morph_step(true)
            .with_billboard_step(true);
        self.balls.thrown.clear();
        // A new scene has its own objects: walk mode starts over on it.
        self.walker = None;
        let target = self.camera.orbit_center;
        self.balls.character = None;
        if !has_character(&self.renderer.scene) {
            self.balls.spawn_character(
                (target.x, target.z),
                CHARACTER_RADIUS,
                &self.renderer.terrain,
            );
        }
        Ok(())
    }

    /// Regenerates the field with the panel's draft settings; the scene keeps its wind,
    /// culling and camera. Blade counts the adapter cannot hold are refused before anything
    /// is allocated.
    pub fn regenerate(&mut self, gpu: &Gpu) {
        let mut scene = self.current_scene();
        scene.field = self.field_draft.clone();
        let result = self.rebuild_field(gpu, &scene);
        self.status = Some(match result {
            Ok(()) => Status::Info(format!(
                "regenerated: {} blades",
                self.renderer.buffers.count
            )),
            Err(e) => Status::Error(format!("not regenerated: {e}")),
        });
    }

    /// Rebuilds the field with the panel's trail map settings (the map is sized with the
    /// tile pool); the scene keeps everything else. A map the adapter cannot hold is
    /// refused and the old one kept.
    pub fn apply_trails(&mut self, gpu: &Gpu) {
        let before = self.renderer.scene.physics.trails.clone();
        self.renderer.scene.physics.trails = self.trails_draft.clone();
        let scene = self.current_scene();
        let result = self.rebuild_field(gpu, &scene);
        self.status = Some(match result {
            Ok(()) => Status::Info("trail map rebuilt (the trails so far are gone)".into()),
            Err(e) => {
                self.renderer.scene.physics.trails = before;
                Status::Error(format!("trail map not changed: {e}"))
            }
        });
    }

    /// Checks `scene` as a file would be and rebuilds the renderer for it, keeping the
    /// simulation's clock; on an error the old renderer stays.
    fn rebuild_field(&mut self, gpu: &Gpu, scene: &Scene) -> Result<()> {
        let checked = validated(scene)?;
        let time = self.renderer.time;
        self.replace_field(gpu, checked)?;
        self.renderer.time = time;
        Ok(())
    }

    fn replace_field(&mut self, gpu: &Gpu, scene: Scene) -> Result<()> {
        let (renderer, _) = build(gpu, scene, self.format)?;
        let overlay = self.renderer.overlay_enabled();
        self.renderer = renderer;
        if overlay {
            self.renderer.enable_overlay(gpu, self.format);
        }
        Ok(())
    }

    /// Rebuilds the wind solver after a change of source or grid resolution.
    pub fn rebuild_wind(&mut self, gpu: &Gpu) {
        if let Err(e) =
            validated(&self.renderer.scene).and_then(|_| self.renderer.rebuild_wind(gpu))
        {
            self.status = Some(Status::Error(format!("wind not changed: {e}")));
        }
    }

    /// Advances everything that lives on the CPU by one frame: camera, balls, the guides
    /// into the scene, the frame budget, the hovered guide point.
    pub fn update(&mut self, gpu: &Gpu) -> f32 {
        let now = Instant::now();
        let wall = self
            .last_frame
            .map_or(1.0 / 60.0, |t| now.duration_since(t).as_secs_f32());
        self.last_frame = Some(now);
        if self.frame > 0 {
            if self.frame_times.len() == PLOT_FRAMES {
                self.frame_times.pop_front();
            }
            self.frame_times.push_back(wall * 1000.0);
            if self
                .budget
                .observe(wall * 1000.0, &mut self.renderer.scene.culling)
                .is_some()
            {
                log::info!("frame budget: {}", self.budget.status());
            }
        }
        let dt = self.fixed_dt.unwrap_or(wall.min(0.1));

        // New guides and "replay the sequence" start at the simulation's clock.
        self.editor.set_clock(self.renderer.time);
        let sim_dt = if self.paused { 0.0 } else { dt };
        let walking = self.camera.mode == CameraMode::Behind;
        if walking {
            if let Some(w) = &mut self.walker {
                w.step(self.input.walk(), sim_dt);
                self.camera.track_heading(w.heading);
            }
        }
        self.pose_walker();
        let camera_input = self.input.take_camera();
        let follow = if walking {
            self.walker_chest()
        } else {
            self.followed()
        };
        self.camera
            .update(&camera_input, dt, &self.renderer.terrain, follow);
        self.camera.view_offset =
            centre_offset(self.size, self.view_region()[0], self.camera.fov_y);

        // In walk mode the arrow keys walk the character, not the ball.
        let steer = if walking {
            Vec2::ZERO
        } else {
            self.steer_direction()
        };
        self.balls.step(
            sim_dt,
            self.renderer.scene.physics.gravity_acceleration,
            &self.renderer.terrain,
            steer,
        );
        self.apply_guides(gpu);
        self.hover = match self.mode {
            Mode::Edit => self.point_under_cursor(),
            Mode::Play => None,
        };
        sim_dt
    }

    /// The arrow keys in world terms: up = the camera's forward on the ground.
    fn steer_direction(&self) -> Vec2 {
        let s = self.input.steer();
        if s == Vec2::ZERO {
            return Vec2::ZERO;
        }
        let f = self.camera.forward();
        let forward = Vec2::new(f.x, f.z).normalize_or(Vec2::NEG_Y);
        let right = Vec2::new(-forward.y, forward.x);
        (forward * s.y + right * s.x).normalize_or_zero()
    }

    /// Copies edited guides into the scene the wind reads. Guides only act through the
    /// fluid, so the first guide switches an analytic-only wind to the fluid.
    fn apply_guides(&mut self, gpu: &Gpu) {
        if self.editor.revision() == self.applied_revision {
            return;
        }
        self.applied_revision = self.editor.revision();
        self.renderer.scene.wind.guides = self.editor.guides().to_vec();
        if !self.editor.guides().is_empty()
            && self.renderer.scene.wind.source == WindSource::Analytic
        {
            self.renderer.scene.wind.source = WindSource::Fluid;
            let fluid = &mut self.renderer.scene.wind.fluid;
            let mut note = String::new();
            // On a CPU adapter a 256² solve costs ~45 ms a frame; 128² keeps 10 fps in reach.
            if self.software && fluid.resolution > SOFTWARE_GRID {
                note = format!(
                    " at {SOFTWARE_GRID}² (a CPU adapter; was {}², see Wind)",
                    fluid.resolution
                );
                fluid.resolution = SOFTWARE_GRID;
            }
            self.rebuild_wind(gpu);
            self.status = Some(Status::Info(format!(
                "wind source set to Fluid{note}: guides push the fluid grid"
            )));
        }
        self.renderer.refresh_overlay_guides(gpu);
    }

    /// Freezes culling at the current camera, or unfreezes it.
    pub fn set_cull_frozen(&mut self, frozen: bool) {
        self.renderer.cull_camera = frozen.then(|| self.view());
    }
}

/// A renderer and an editor for a scene (the field generated, its size checked first): the
/// window draws sward's whole world through the embedding API (`GrassRenderer::new_world`,
/// `begin_world` / `finish_world`), as any host may.
fn build(gpu: &Gpu, scene: Scene, format: wgpu::TextureFormat) -> Result<(GrassRenderer, Editor)> {
    let renderer = GrassRenderer::world_of_checked(gpu, scene, format)?;
    let editor = Editor::new(
        renderer.scene.wind.guides.clone(),
        renderer.scene.terrain.size,
    )
    .map_err(|e| Error::Invalid(format!("wind.guides: {e}")))?;
    Ok((renderer, editor))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 3D view is right of the panel, over the window's whole height; a panel that
    /// leaves less than MIN_VIEW_PX (or a window smaller than the panel) gives the view the
    /// whole window back, under the panel, rather than a sliver or nothing.
    #[test]
    fn the_view_region_is_beside_the_panel_while_it_fits() {
        assert_eq!(view_region((1280, 720), 345), [345, 0, 935, 720]);
        assert_eq!(view_region((1280, 720), 0), [0, 0, 1280, 720]);
        assert_eq!(
            view_region((1280, 720), 1280 - MIN_VIEW_PX),
            [1216, 0, 64, 720]
        );
        assert_eq!(
            view_region((1280, 720), 1280 - MIN_VIEW_PX + 1),
            [0, 0, 1280, 720]
        );
        assert_eq!(view_region((200, 100), 345), [0, 0, 200, 100]);
        assert_eq!(view_region((1280, 720), u32::MAX), [0, 0, 1280, 720]);
        assert_eq!(view_region((0, 0), 0), [0, 0, 0, 0]);
    }
}
