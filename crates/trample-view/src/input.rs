//! Keys and what they do, with no window dependency: the window turns its
//! key events into [`Key`]s, [`Input::key`] keeps the held keys and turns
//! presses into [`Action`]s. Tests script key sequences through it.

/// The keys the viewer listens to (window-independent names).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Key {
    /// Arrow up: accelerate the driven object.
    ArrowUp,
    /// Arrow down: brake, then reverse.
    ArrowDown,
    /// Arrow left: steer left.
    ArrowLeft,
    /// Arrow right: steer right.
    ArrowRight,
    /// Free-fly forward.
    W,
    /// Free-fly left.
    A,
    /// Free-fly back.
    S,
    /// Free-fly right.
    D,
    /// Free-fly down.
    Q,
    /// Free-fly up.
    E,
    /// Pause / resume.
    Space,
    /// One step while paused.
    N,
    /// Reset the field (and apply the pending rebuild settings).
    R,
    /// Restart the objects' paths from their start.
    T,
    /// Drive the first object with the arrows / let it follow its path.
    G,
    /// Next camera: orbit → free-fly → scene path.
    C,
    /// Next debug view.
    V,
    /// Screenshot to a PNG.
    P,
    /// Show / hide the panel.
    H,
    /// Precision − 1.
    BracketLeft,
    /// Precision + 1.
    BracketRight,
    /// Camera speed ×2 while held (free-fly).
    Shift,
}

/// What a key press asks for (held keys act through [`Held`] instead).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Action {
    /// Pause or resume the simulation.
    TogglePause,
    /// Take one step (pauses first).
    SingleStep,
    /// Rebuild the field at rest with the current settings.
    ResetField,
    /// Objects start their paths again.
    RestartPath,
    /// Arrow keys drive the first object / it follows its path.
    ToggleDrive,
    /// Next camera mode.
    NextCamera,
    /// Next debug view.
    NextDebugView,
    /// Write a screenshot.
    Screenshot,
    /// Show or hide the panel.
    TogglePanel,
    /// Change the collision precision by this much (kept in 1..=10).
    Precision(i32),
}

/// The action of a key press, if the key has one (see [`Key`] for the map).
#[must_use]
pub fn action_of(key: Key) -> Option<Action> {
    Some(match key {
        Key::Space => Action::TogglePause,
        Key::N => Action::SingleStep,
        Key::R => Action::ResetField,
        Key::T => Action::RestartPath,
        Key::G => Action::ToggleDrive,
        Key::C => Action::NextCamera,
        Key::V => Action::NextDebugView,
        Key::P => Action::Screenshot,
        Key::H => Action::TogglePanel,
        Key::BracketLeft => Action::Precision(-1),
        Key::BracketRight => Action::Precision(1),
        _ => return None,
    })
}

/// Keys held down now, as axes in [-1, 1].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Held {
    up: bool,
    down: bool,
    left: bool,
    right: bool,
    w: bool,
    a: bool,
    s: bool,
    d: bool,
    q: bool,
    e: bool,
    /// Shift is held.
    pub shift: bool,
}

impl Held {
    /// Arrow up − arrow down: throttle of the driven object.
    #[must_use]
    pub fn throttle(&self) -> f32 {
        axis(self.up, self.down)
    }

    /// Arrow left − arrow right: steering (positive turns left, i.e.
    /// counter-clockwise seen from above, a positive turn about +y).
    #[must_use]
    pub fn steer(&self) -> f32 {
        axis(self.left, self.right)
    }

    /// Free-fly movement: (right, up, forward) from D−A, E−Q, W−S.
    #[must_use]
    pub fn fly(&self) -> glam::Vec3 {
        glam::Vec3::new(
            axis(self.d, self.a),
            axis(self.e, self.q),
            axis(self.w, self.s),
        )
    }

    /// Any arrow key is held.
    #[must_use]
    pub fn arrows(&self) -> bool {
        self.up || self.down || self.left || self.right
    }
}

fn axis(plus: bool, minus: bool) -> f32 {
    f32::from(u8::from(plus)) - f32::from(u8::from(minus))
}

/// Keyboard state: the held keys.
#[derive(Clone, Debug, Default)]
pub struct Input {
    /// Keys held now.
    pub held: Held,
}

impl Input {
    /// Records a key event; returns the action of a press (not of a
    /// release, nor of a repeat: `repeat` is true for auto-repeated presses).
    pub fn key(&mut self, key: Key, pressed: bool, repeat: bool) -> Option<Action> {
        let h = &mut self.held;
        let slot = match key {
            Key::ArrowUp => Some(&mut h.up),
            Key::ArrowDown => Some(&mut h.down),
            Key::ArrowLeft => Some(&mut h.left),
            Key::ArrowRight => Some(&mut h.right),
            Key::W => Some(&mut h.w),
            Key::A => Some(&mut h.a),
            Key::S => Some(&mut h.s),
            Key::D => Some(&mut h.d),
            Key::Q => Some(&mut h.q),
            Key::E => Some(&mut h.e),
            Key::Shift => Some(&mut h.shift),
            _ => None,
        };
        if let Some(slot) = slot {
            *slot = pressed;
            return None;
        }
        if pressed && !repeat {
            action_of(key)
        } else {
            None
        }
    }

    /// Forgets every held key (the window lost focus: no key stays stuck).
    pub fn release_all(&mut self) {
        self.held = Held::default();
    }
}
