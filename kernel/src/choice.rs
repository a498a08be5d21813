//! Closed sets of named options: a strategy's kinds (how lights are selected, how sphere lights
//! are sampled, ...), the combination methods, the sample streams. Each set is one enum whose
//! names, summaries and list are written once, by the kernel's macro `choices!`; the scene format,
//! the command line, the browser page and the reports all ask it through [`Choice`].

/// A closed set of named options.
pub trait Choice: Copy + PartialEq + core::fmt::Debug + 'static {
    /// What the set is called (in errors: "unknown light selection ...").
    const WHAT: &'static str;
    /// Every option, in the order of the lists that show them.
    const ALL: &'static [Self];

    /// The option's name (command line, scene files, reports).
    fn name(self) -> &'static str;

    /// One line about the option (command-line help).
    fn summary(self) -> &'static str;

    /// The option called `name`.
    fn from_name(name: &str) -> Option<Self> {
        Self::ALL.iter().copied().find(|c| c.name() == name)
    }
}

/// Defines a [`Choice`] enum: its variants with their names and summaries, and the list of all
/// of them; with `Display` (the name) and, on `defmt` builds, `defmt::Format`.
///
/// ```
/// picomis::choices! {
///     /// A colour.
///     pub enum Colour: "colour" {
///         /// Red.
///         Red = "red", "the colour of blood";
///         /// Blue.
///         Blue = "blue", "the colour of the sky";
///     }
/// }
/// use picomis::choice::Choice;
/// assert_eq!(Colour::from_name("blue"), Some(Colour::Blue));
/// assert_eq!(Colour::ALL, [Colour::Red, Colour::Blue]);
/// assert_eq!(Colour::Red.to_string(), "red");
/// ```
// Exported (`#[macro_export]`) because the kernel's option enums are defined with it from every
// module; hidden because it is not API: a user reads the enums through [`Choice`].
#[doc(hidden)]
#[macro_export]
macro_rules! choices {
    (
        $(#[$meta:meta])*
        pub enum $name:ident: $what:literal {
            $( $(#[$vmeta:meta])* $variant:ident = $vname:literal, $summary:literal; )+
        }
    ) => {
        $(#[$meta])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        #[cfg_attr(feature = "defmt", derive(defmt::Format))]
        pub enum $name {
            $( $(#[$vmeta])* $variant, )+
        }

        impl $name {
            /// Every option, in the order of the lists that show them.
            pub const ALL: [$name; [$($vname),+].len()] = [$($name::$variant),+];

            /// The option's name (command line, scene files, reports).
            pub const fn name(self) -> &'static str {
                match self {
                    $( $name::$variant => $vname, )+
                }
            }

            /// One line about the option (command-line help).
            pub const fn summary(self) -> &'static str {
                match self {
                    $( $name::$variant => $summary, )+
                }
            }

            /// The option called `name`.
            pub fn from_name(name: &str) -> Option<Self> {
                <Self as $crate::choice::Choice>::from_name(name)
            }
        }

        impl $crate::choice::Choice for $name {
            const WHAT: &'static str = $what;
            const ALL: &'static [Self] = &$name::ALL;

            fn name(self) -> &'static str {
                $name::name(self)
            }

            fn summary(self) -> &'static str {
                $name::summary(self)
            }
        }

        impl core::fmt::Display for $name {
            fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
                f.write_str($crate::choice::Choice::name(*self))
            }
        }
    };
}

/// The names of every option of `C`, for messages: `a, b or c`.
pub struct Names<C>(core::marker::PhantomData<C>);

impl<C: Choice> Names<C> {
    /// The names of every option of `C`.
    pub const fn of() -> Self {
        Names(core::marker::PhantomData)
    }
}

impl<C: Choice> core::fmt::Display for Names<C> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let last = C::ALL.len().saturating_sub(1);
        for (i, c) in C::ALL.iter().enumerate() {
            let sep = match i {
                0 => "",
                i if i == last => " or ",
                _ => ", ",
            };
            write!(f, "{sep}{}", c.name())?;
        }
        Ok(())
    }
}
