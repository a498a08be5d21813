//! Typed errors returned while a scene or render settings are built. Nothing in the kernel panics
//! on user data: every value is checked once, here, at construction.

use core::fmt;

/// Which value of a scene entry is wrong.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Field {
    /// Sphere center.
    Center,
    /// Sphere radius.
    Radius,
    /// A quad corner.
    Corner,
    /// Emitted radiance.
    Radiance,
    /// Point-light intensity.
    Intensity,
    /// Point-light position.
    Position,
    /// Lambertian albedo.
    Albedo,
    /// GGX alpha.
    Alpha,
    /// Specular reflectance.
    Reflectance,
    /// Camera origin.
    CameraOrigin,
    /// Camera target.
    CameraTarget,
    /// Camera up vector.
    CameraUp,
    /// Field of view.
    FieldOfView,
    /// Near clip distance.
    NearClip,
    /// Film width or height.
    FilmSize,
    /// Samples per pixel.
    SamplesPerPixel,
    /// Light or BSDF sample count.
    TechniqueSamples,
    /// Power-heuristic exponent.
    Beta,
    /// Cutoff-heuristic threshold.
    CutoffAlpha,
    /// Probability of the light technique in the one-sample model.
    CLight,
    /// Light samples following the receiver's lobe (a build without the `lobe` feature).
    LobeMixing,
}

/// Which fixed-capacity collection of a scene is full.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Collection {
    /// Shapes.
    Shapes,
    /// Lights (area emitters and point lights).
    Lights,
    /// Materials.
    Materials,
}

/// Why a scene, a camera or render settings could not be built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum SceneError {
    /// The build's capacity for this collection is exhausted.
    CapacityExceeded(Collection),
    /// A number is NaN or infinite.
    NonFinite(Field),
    /// A value that must be positive is zero or negative.
    NonPositive(Field),
    /// A value is negative or outside its allowed range.
    OutOfRange(Field),
    /// A direction (or a difference of points) has zero length.
    ZeroDirection(Field),
    /// The camera's up vector is parallel to its view direction.
    UpParallelToView,
    /// A quad has zero area (coincident or collinear corners).
    DegenerateQuad,
    /// A quad's corners do not form a parallelogram (p2 != p1 + p3 - p0).
    NotParallelogram,
    /// A material index does not name a material of the scene.
    UnknownMaterial,
    /// A shape index does not name a shape of the scene.
    UnknownShape,
    /// The shape already carries an emitter.
    AlreadyEmitting,
    /// Both sample counts are zero: no technique is left.
    NoTechnique,
    /// The control variate with a method that draws no light samples: its closed form belongs
    /// to the light technique.
    ControlVariateWithoutLight,
    /// The settings name other strategies than the estimator was built for.
    StrategyMismatch,
    /// A scene image's words do not hold a scene (`Scene::load_image`).
    BadImage,
    /// The fixed-point format chosen for the scene cannot represent shape `entry` accurately
    /// (feature `fixed`).
    #[cfg(feature = "fixed")]
    #[cfg_attr(docsrs, doc(cfg(feature = "fixed")))]
    NotRepresentable {
        /// Index of the shape.
        entry: u16,
        /// Why.
        reason: Unrepresentable,
    },
}

/// Why the fixed-point format cannot represent a shape (feature `fixed`).
#[cfg(feature = "fixed")]
#[cfg_attr(docsrs, doc(cfg(feature = "fixed")))]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Unrepresentable {
    /// The scene's extent is not finite, or too large for an f32 scale factor (beyond 2^120).
    Extent,
    /// A sphere radius or quad edge is below 2^12 units of the scale the extent sets.
    TooSmall,
    /// A quad's dual axes are too long for the format (a nearly degenerate parallelogram).
    Skewed,
}

#[cfg(feature = "fixed")]
impl Unrepresentable {
    /// The reason in words (for logs without `core::fmt`).
    pub fn as_str(self) -> &'static str {
        match self {
            Unrepresentable::Extent => "the scene's extent is not finite or beyond 2^120",
            Unrepresentable::TooSmall => "it is too small relative to the scene's extent (below 2^-14 of it)",
            Unrepresentable::Skewed => "its quad is too skewed",
        }
    }
}

#[cfg(feature = "fixed")]
impl fmt::Display for Unrepresentable {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl fmt::Display for Field {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Field::Center => "center",
            Field::Radius => "radius",
            Field::Corner => "corner",
            Field::Radiance => "radiance",
            Field::Intensity => "intensity",
            Field::Position => "position",
            Field::Albedo => "albedo",
            Field::Alpha => "alpha",
            Field::Reflectance => "specular_reflectance",
            Field::CameraOrigin => "origin",
            Field::CameraTarget => "target",
            Field::CameraUp => "up",
            Field::FieldOfView => "fov_deg",
            Field::NearClip => "near_clip",
            Field::FilmSize => "film size",
            Field::SamplesPerPixel => "spp",
            Field::TechniqueSamples => "sample count",
            Field::Beta => "power-heuristic beta",
            Field::CutoffAlpha => "cutoff alpha",
            Field::CLight => "c_light",
            Field::LobeMixing => "lobe_mixing",
        })
    }
}

impl fmt::Display for Collection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Collection::Shapes => "shapes",
            Collection::Lights => "lights",
            Collection::Materials => "materials",
        })
    }
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SceneError::CapacityExceeded(c) => write!(f, "too many {c} for this build"),
            SceneError::NonFinite(x) => write!(f, "{x} is not a finite number"),
            SceneError::NonPositive(x) => write!(f, "{x} must be positive"),
            SceneError::OutOfRange(x) => write!(f, "{x} is out of range"),
            SceneError::ZeroDirection(x) => write!(f, "{x} gives a zero-length direction"),
            SceneError::UpParallelToView => f.write_str("camera up is parallel to the view direction"),
            SceneError::DegenerateQuad => f.write_str("quad has zero area"),
            SceneError::NotParallelogram => {
                f.write_str("quad corners are not a parallelogram (p2 != p1 + p3 - p0)")
            }
            SceneError::UnknownMaterial => f.write_str("unknown material"),
            SceneError::UnknownShape => f.write_str("unknown shape"),
            SceneError::AlreadyEmitting => f.write_str("shape already has an emitter"),
            SceneError::NoTechnique => f.write_str("both sample counts are zero"),
            SceneError::ControlVariateWithoutLight => {
                f.write_str("the control variate needs the light technique (a method with light samples)")
            }
            SceneError::BadImage => f.write_str("the scene image is damaged or of another version"),
            SceneError::StrategyMismatch => {
                f.write_str("the settings name other strategies than the estimator was built for")
            }
            #[cfg(feature = "fixed")]
            SceneError::NotRepresentable { entry, reason } => {
                write!(f, "fixed point cannot represent shape {entry}: {reason}")
            }
        }
    }
}

impl core::error::Error for SceneError {}
