package jsref.runtime;

/** A message as Jadescript code sees it: performative (lower case, as written
    in the program), content (a Jadescript value) and the sender's name
    ({@code "host"} for the host's messages). */
public record Message(String performative, Object content, String sender) {}
