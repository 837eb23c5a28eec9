# Functions defined at column 0 (the house style: namespaces are not indented) whose body,
# from the line of the signature to the closing brace at column 0, exceeds LIMIT lines.
FNR == 1 { infn = 0 }
{
    line = $0
    if (!infn) {
        if (line ~ /^[A-Za-z_].*\)[^;]*\{[[:space:]]*$/ && line !~ /^(namespace|struct|class|enum|union|extern)/ && line !~ /=[[:space:]]*\{/) {
            infn = 1; start = FNR; name = line
        } else if (line ~ /^[A-Za-z_].*[(,][[:space:]]*$/ && line !~ /^(namespace|struct|class)/) {
            pending = line; pstart = FNR
        } else if (pending != "" && line ~ /^[[:space:]].*\)[^;]*\{[[:space:]]*$/) {
            infn = 1; start = pstart; name = pending; pending = ""
        } else if (line !~ /^[[:space:]]/) pending = ""
        next
    }
    if (line ~ /^\}/) {
        n = FNR - start + 1
        if (n > LIMIT) printf "%s:%d: %d lines: %s\n", FILENAME, start, n, substr(name, 1, 90)
        infn = 0
    }
}
