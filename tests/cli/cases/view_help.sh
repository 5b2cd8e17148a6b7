# hovox view --help: the usage, what a page shows, the options and the keys
$HOVOX view --help
