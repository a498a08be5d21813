//! Typed indices of a scene's shapes, lights and materials. Scene methods take and return these
//! instead of bare integers, so a light index cannot be passed where a shape index is meant; an
//! index that names nothing is answered with `None` (or zero), never a panic.

/// Index of a shape in its scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ShapeId(u16);

/// Index of a light in its scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct LightId(u16);

/// Index of a material in its scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct MaterialId(u16);

macro_rules! index_type {
    ($t:ident) => {
        impl $t {
            /// The id of entry `index` (whether the scene has it is checked where it is used).
            #[inline]
            pub const fn new(index: u16) -> Self {
                Self(index)
            }

            /// The index.
            #[inline]
            pub fn index(self) -> usize {
                usize::from(self.0)
            }

            /// The index as stored.
            #[inline]
            pub const fn raw(self) -> u16 {
                self.0
            }
        }
    };
}

index_type!(ShapeId);
index_type!(LightId);
index_type!(MaterialId);
