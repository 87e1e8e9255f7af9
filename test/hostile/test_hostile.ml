(* What an adversarial user tries: the one JSON reader (lib/json), the
   events file read once from a file, a pipe or a FIFO, every reader linear
   and bounded, the commands' one-line errors. *)

let check = Alcotest.(check bool)
let root = Test_support.Support.root

(* ------------------------------------------------------------ JSON *)

let read s = Json_read.of_string s

let short s = if String.length s > 60 then String.sub s 0 60 ^ "..." else s

let accepts s () =
  match read s, Yojson.Safe.from_string s with
  | Ok v, w -> Alcotest.(check string) (short s) (Yojson.Safe.to_string w) (Yojson.Safe.to_string v)
  | Error e, _ -> Alcotest.failf "%S refused: %s" (short s) (Json_read.to_string e)

let refuses ?at s () =
  match read s with
  | Ok v -> Alcotest.failf "%S accepted as %s" (short s) (short (Yojson.Safe.to_string v))
  | Error e ->
    check "one printable line" true (String.for_all (fun c -> c >= ' ' && c <= '~') e.message);
    Option.iter (fun (l, c) -> Alcotest.(check (pair int int)) ("where: " ^ e.message) (l, c) (e.line, e.column)) at

let deep d = String.make d '[' ^ String.make d ']'

let json_cases = [
  "an object", `Quick, accepts {|{"a": [1, -2, 3.5, 1e3, true, false, null], "b": {"c": "d\u00e9\n"}}|};
  "a pair of surrogates", `Quick, accepts {|"\ud83d\ude00"|};
  "an integer beyond int", `Quick, accepts "123456789012345678901234567890";
  "1,000 deep (the limit)", `Quick, accepts (deep 1000);
  "1,001 deep", `Quick, refuses ~at:(1, 1001) (deep 1001);
  "200,000 deep: an error, no stack overflow", `Quick, refuses (deep 200_000);
  "200,000 objects deep", `Quick, refuses (String.concat "" (List.init 200_000 (fun _ -> {|{"a":|})) ^ "1" ^ String.make 200_000 '}');
  "a raw NUL in a string", `Quick, refuses ~at:(1, 3) "\"a\000b\"";
  "a raw line feed in a string", `Quick, refuses "\"a\nb\"";
  "a raw tab in a string", `Quick, refuses "\"a\tb\"";
  "a raw NUL after the value", `Quick, refuses "{}\000";
  "invalid UTF-8 in a string", `Quick, refuses ~at:(1, 3) "\"a\xffb\"";
  "an overlong UTF-8 sequence", `Quick, refuses "\"\xc0\xaf\"";
  "an encoded surrogate", `Quick, refuses "\"\xed\xa0\x80\"";
  "a lone surrogate escape", `Quick, refuses {|"\ud800"|};
  "a lone second surrogate", `Quick, refuses {|"\udc00x"|};
  "a key twice", `Quick, refuses ~at:(1, 10) {|{"a": 1, "a": 2}|};
  "a key twice among many", `Quick,
  refuses ("{" ^ String.concat ", " (List.init 40 (fun i -> Printf.sprintf "\"k%d\": %d" i i)) ^ ", \"k7\": 0}");
  "NaN", `Quick, refuses "NaN";
  "Infinity", `Quick, refuses "[Infinity]";
  "a leading zero", `Quick, refuses "012";
  "a leading plus", `Quick, refuses "+1";
  "a bare point", `Quick, refuses ".5";
  "a point with no digit", `Quick, refuses "1.";
  "an exponent with no digit", `Quick, refuses "1e";
  "a trailing comma", `Quick, refuses "[1, 2,]";
  "a comment", `Quick, refuses "[1] // no";
  "single quotes", `Quick, refuses "['a']";
  "an unknown escape", `Quick, refuses {|"\x41"|};
  "two values", `Quick, refuses ~at:(1, 4) "{} {}";
  "nothing", `Quick, refuses "";
  "an unclosed string", `Quick, refuses "\"abc";
  "an unclosed array", `Quick, refuses "[1, 2";
  "a second line", `Quick, refuses ~at:(2, 4) "[1,\n 2 x]";
]

(* Any value Yojson writes, the reader reads back the same. *)
let yojson_gen =
  let open QCheck.Gen in
  let text = string_size ~gen:(oneof [ printable; char; return '\xc3' ]) (0 -- 12) in
  let valid t = match Utf8.first_invalid t with None -> t | Some _ -> "x" in
  sized_size (0 -- 6) (fix (fun self n ->
      let leaf = oneof [
          map (fun i -> `Int i) int; map (fun f -> `Float f) (float_range (-1e6) 1e6);
          map (fun s -> `String (valid s)) text; return `Null; map (fun b -> `Bool b) bool ] in
      if n = 0 then leaf
      else frequency [
          3, leaf;
          1, map (fun l -> `List l) (list_size (0 -- 4) (self (n / 2)));
          1, map (fun l ->
              let l = List.mapi (fun i (k, v) -> (valid k ^ string_of_int i, v)) l in
              `Assoc l) (list_size (0 -- 4) (pair text (self (n / 2)))) ]))

let round_trip =
  Test_support.Support.qcheck ~count:2000 "what Yojson writes, the reader reads the same"
    (QCheck.make ~print:Yojson.Safe.to_string yojson_gen) (fun (v : Yojson.Safe.t) ->
        let s = Yojson.Safe.to_string v in
        match Json_read.of_string s with
        | Ok w -> Yojson.Safe.to_string w = s
        | Error e -> QCheck.Test.fail_reportf "%s: %s" s (Json_read.to_string e))

let () =
  Alcotest.run "hostile"
    [ "json", json_cases @ [ round_trip ] ]
