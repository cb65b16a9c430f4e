//! The members of a record of parameters in user units, to name in an error: as a record's
//! member or a Python keyword (`speed_kmh`) or as the command-line option that sets it
//! (`--speed-kmh`). [`fields!`] declares such an enum once for the flight parameters
//! ([`crate::params::Field`]) and the layering ([`crate::layer_params::LayerField`]).

/// Declares `pub enum $name` of the members `$variant = "name"` (each documented by its name,
/// then by what follows it), with `ALL` (every member, in order), `NAMES` (their names, in
/// order), `name()` and `option()`.
macro_rules! fields {
    (
        $(#[$meta:meta])*
        pub enum $name:ident {
            $($(#[$variant_meta:meta])* $variant:ident = $text:literal,)*
        }
    ) => {
        $(#[$meta])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        pub enum $name {
            $(
                #[doc = concat!("`", $text, "`.")]
                $(#[$variant_meta])*
                $variant,
            )*
        }

        impl $name {
            /// Every member, in order.
            pub const ALL: [$name; [$($text),*].len()] = [$($name::$variant),*];

            /// The names of every member, in order.
            pub const NAMES: [&'static str; [$($text),*].len()] = [$($text),*];

            /// The member's name, e.g. `speed_kmh`.
            pub const fn name(self) -> &'static str {
                match self {
                    $($name::$variant => $text,)*
                }
            }

            /// The command-line option that sets it, e.g. `--speed-kmh`.
            pub fn option(self) -> String {
                format!("--{}", self.name().replace('_', "-"))
            }
        }
    };
}

pub(crate) use fields;
