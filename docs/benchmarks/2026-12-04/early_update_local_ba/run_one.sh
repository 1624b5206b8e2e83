#!/usr/bin/env bash
cd /work/main
DS=$1; i=$2; shift 2
name=$(basename $DS); mkdir -p /tmp/ab/$name
for tag in "$@"; do
  out=/tmp/ab/$name/${tag}_$i; rm -rf $out
  case $tag in
    s2) make eval DATASET=$DS MODE=split OUT=$out > $out.log 2>&1 ;;
    sd) SLAM_CONFIG=/tmp/ab/slam_div.yaml make eval DATASET=$DS MODE=split OUT=$out > $out.log 2>&1 ;;
    m2) make eval DATASET=$DS MODE=monolithic OUT=$out > $out.log 2>&1 ;;
  esac
  echo "$(date +%T) $name $tag $i rc=$?"
done
