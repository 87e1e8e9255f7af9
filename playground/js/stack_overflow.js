// Linked by js_of_ocaml after its own runtime (playground/js/dune): the
// runtime's caml_wrap_exception, which maps the engine's stack overflow to
// OCaml's Stack_overflow, with one change. The original tests the message
// with a regular expression, and running a regular expression at the bottom
// of an exhausted stack overflows too: a program's endless recursion then
// became an internal error instead of the interpreter's run-time error
// "recursion too deep" (R7), as the command line reports it. This version
// compares strings only.

//Provides: caml_wrap_exception const (const)
//Requires: caml_global_data,caml_string_of_jsstring,caml_named_value
//Requires: caml_return_exn_constant
function caml_wrap_exception(e) {
  if (e instanceof Array) return e;
  var m = (e && typeof e.message === "string") ? e.message.toLowerCase() : "";
  // Stack_overflow: chrome, safari (RangeError), firefox (InternalError)
  if ((globalThis.RangeError && e instanceof globalThis.RangeError
       && m.indexOf("maximum call stack") >= 0)
      || (globalThis.InternalError && e instanceof globalThis.InternalError
          && m.indexOf("too much recursion") >= 0)
      // a regular expression run elsewhere at the bottom of the stack
      || (globalThis.SyntaxError && e instanceof globalThis.SyntaxError
          && m.indexOf("stack overflow") >= 0))
    return caml_return_exn_constant(caml_global_data.Stack_overflow);
  // Wrap Error in Js.Error exception
  if (e instanceof globalThis.Error && caml_named_value("jsError"))
    return [0, caml_named_value("jsError"), e];
  // fallback: wrapped in Failure
  return [0, caml_global_data.Failure, caml_string_of_jsstring(String(e))];
}
