//! `machine!`: declarative machine models compiled to specialised code.
//! Until the equation-compiler issue lands this crate only reserves the name.
use proc_macro::TokenStream;

/// Placeholder: the compiler issue fills this with parse -> IR -> check -> derive -> emit.
#[proc_macro]
pub fn machine(input: TokenStream) -> TokenStream {
    let _ = input;
    quote::quote!(compile_error!("machine! is not implemented yet");).into()
}
