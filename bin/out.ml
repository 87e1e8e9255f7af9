(* Writing what a command outputs: every write is checked, so that a full disk
   or a closed pipe is one line "jadescript-ref: error: ..." and exit status 1,
   never an uncaught exception at exit. *)

exception Failed of string

let error msg = prerr_endline ("jadescript-ref: error: " ^ msg)

(* Once a write to the standard output failed and was reported, the channel is
   closed (its buffer dropped), so that neither [finish] nor the exit of the
   program tries again and reports it twice. *)
let reported = ref false
let give_up_stdout () = reported := true; close_out_noerr stdout

(* Standard output, checked. *)
let print s =
  try print_string s with Sys_error m -> raise (Failed ("cannot write the standard output: " ^ m))

(* Replace a whole file, checked: written beside it, then renamed over it,
   so that a failed write (a full disk) leaves the old file as it was.
   Error: the system's reason. *)
let replace path s =
  (* a link is followed: its target is rewritten, and the link stays *)
  let path = match Unix.lstat path with
    | { Unix.st_kind = Unix.S_LNK; _ } -> (try Unix.realpath path with Unix.Unix_error _ -> path)
    | _ -> path
    | exception Unix.Unix_error _ -> path in
  (* a file the user may not write is not replaced (a rename beside it
     would replace it all the same, as the folder is writable) *)
  match Unix.access path [ Unix.W_OK ]; (Unix.stat path).Unix.st_perm with
  | exception Unix.Unix_error (e, _, _) -> Error (path ^ ": " ^ Unix.error_message e)
  | perm when perm land 0o222 = 0 ->
    (* read-only for everyone (the super-user too would pass [access]) *)
    Error (path ^ ": the file is read-only")
  | _ ->
  match Filename.temp_file ~temp_dir:(Filename.dirname path) ".jsref" ".tmp" with
  | exception Sys_error m -> Error m
  | tmp ->
    let oc = open_out_bin tmp in
    match
      output_string oc s; close_out oc;
      (try Unix.chmod tmp (Unix.stat path).Unix.st_perm with Unix.Unix_error _ -> ());
      Sys.rename tmp path
    with
    | () -> Ok ()
    | exception Sys_error m ->
      close_out_noerr oc; (try Sys.remove tmp with Sys_error _ -> ()); Error m

(* [protect f]: f's exit status, or 1 with one line when a write failed. *)
let protect f = match f () with
  | code -> code
  | exception Failed m -> error m; give_up_stdout (); 1

(* The end of every command: what is still buffered for the standard output
   is flushed here, and a failure is reported (then the channel is closed, so
   that nothing tries again at exit). *)
let finish code =
  if !reported then code
  else match Format.pp_print_flush Format.std_formatter (); flush stdout with
    | () -> code
    | exception Sys_error m ->
      error ("cannot write the standard output: " ^ m);
      give_up_stdout ();
      1
