//! Writing and reading images, and comparing them.

pub mod compare;
pub mod image;
pub mod npy;

pub use self::image::{check_writable, read_image, write_image, ImageFormat};
