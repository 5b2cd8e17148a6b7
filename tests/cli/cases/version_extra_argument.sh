$HOVOX --version extra; echo "rc=$?"
